"""MkDocs hooks: env pages take their reference sections from the envs' own docstrings.

A page line ``<!-- docstring: babyrobot_marl.race_v0 -->`` (a module) or
``<!-- docstring: babyrobot_marl.envs.single:BabyRobotEnv -->`` (an object in a module) is
replaced by that docstring from its first ``## `` heading on, so the page and ``help(env)``
cannot drift apart (PettingZoo's site builds its env pages from docstrings the same way).
"""

from __future__ import annotations

import importlib
import inspect
import re

MARKER = re.compile(r"^<!-- docstring: ([\w.]+)(?::(\w+))? -->$", re.MULTILINE)


def docstring_sections(module: str, attr: str | None) -> str:
    obj = importlib.import_module(module)
    if attr:
        obj = getattr(obj, attr)
    doc = inspect.cleandoc(obj.__doc__ or "")
    start = re.search(r"^## ", doc, re.MULTILINE)
    if start is None:
        raise ValueError(f"docstring of {module}:{attr} has no '## ' section to include")
    return doc[start.start():]


def on_page_markdown(markdown: str, page, config, files) -> str:
    return MARKER.sub(lambda m: docstring_sections(m.group(1), m.group(2)), markdown)
