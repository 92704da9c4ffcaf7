"""TEMPORARY stand-in (helper r25b) for issue 25's envs/encodings.py: re-exports only. Dropped at merge for r25a's module."""

from ..encodings import Encoder

__all__ = ["Encoder"]
