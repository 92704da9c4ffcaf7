"""The optional packages of the ``train`` extra, imported on demand with a clear message."""

from __future__ import annotations

import importlib
from types import ModuleType

TRAIN_EXTRA = ("stable_baselines3", "supersuit", "imageio")
INSTALL_HINT = "pip install 'babyrobot_marl[train]'"


class MissingTrainExtraError(ImportError):
    """A package of the ``train`` extra is not installed."""


def require_train(*modules: str) -> list[ModuleType]:
    """Import ``modules`` (default: all of the ``train`` extra) or raise ``MissingTrainExtraError``
    naming the missing ones and the install command."""
    names = modules or TRAIN_EXTRA
    found, missing = [], []
    for name in names:
        try:
            found.append(importlib.import_module(name))
        except ImportError:
            missing.append(name)
    if missing:
        raise MissingTrainExtraError(f"training needs {', '.join(missing)} (the 'train' extra): {INSTALL_HINT}")
    return found
