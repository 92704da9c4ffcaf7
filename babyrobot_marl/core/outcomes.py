"""TEMPORARY stand-in (helper r25b) for issue 25's core/outcomes.py: re-exports only. Dropped at merge for r25a's module."""

from ..envs.common import OUTCOME_NAMES

__all__ = ["OUTCOME_NAMES"]
