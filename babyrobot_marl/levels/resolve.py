"""TEMPORARY stand-in (helper r25b) for issue 25's levels/resolve.py: re-exports only. Dropped at merge for r25a's module."""

from ..envs.common import resolve_level

__all__ = ["resolve_level"]
