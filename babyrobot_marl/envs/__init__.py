"""Env adapters over the shared core: Gymnasium (single robot) and PettingZoo (race)."""

from .single import BabyRobotEnv

__all__ = ["BabyRobotEnv"]
