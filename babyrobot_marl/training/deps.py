"""The optional packages of the ``train`` extra, imported on demand with a clear message."""

from __future__ import annotations

import contextlib
import functools
import importlib
from collections.abc import Iterator
from types import ModuleType
from typing import Any

TRAIN_EXTRA = ("stable_baselines3", "supersuit", "imageio")
# torch first, from PyTorch's CPU index: '[train]' alone pulls torch's CUDA build from PyPI (about 3 GB)
TORCH_CPU = "pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu"
INSTALL_HINT = f"{TORCH_CPU}, then pip install 'babyrobot_marl[train]' (torch first: its CPU build, not the ~3 GB CUDA one)"


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
        raise MissingTrainExtraError(f"this needs {', '.join(missing)} (the 'train' extra): {INSTALL_HINT}")
    return found


@functools.cache
def torch_module() -> Any:
    """torch, imported once (``MissingTrainExtraError`` without it): the trainer's and the policies' one way to it."""
    (torch,) = require_train("torch")
    return torch


@contextlib.contextmanager
def torch_threads(threads: int | None) -> Iterator[None]:
    """Run with ``threads`` torch threads (None: leave torch's setting), restored afterwards."""
    torch = torch_module()
    before = torch.get_num_threads()
    if threads is not None:
        torch.set_num_threads(threads)
    try:
        yield
    finally:
        torch.set_num_threads(before)
