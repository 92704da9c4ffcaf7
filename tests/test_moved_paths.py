"""Issue 25: the public import paths that moved keep working for one release, with a
``DeprecationWarning`` naming the new path, and give the very same objects as the new path."""

from __future__ import annotations

import importlib
import sys

import pytest

# old path -> (new path the warning names, {name: module it now lives in})
MOVED = {
    "babyrobot_marl.checks": ("babyrobot_marl.core.checks", {
        "check_int": "babyrobot_marl.core.checks", "check_real": "babyrobot_marl.core.checks",
        "real_array": "babyrobot_marl.core.checks", "shown": "babyrobot_marl.core.checks",
        "MAX_LEVEL_CELLS": "babyrobot_marl.core.checks", "MAX_LEVEL_TEXT_CHARS": "babyrobot_marl.core.checks",
        "MAX_DENSE_STATES": "babyrobot_marl.core.checks", "MAX_BATCH_ENVS": "babyrobot_marl.core.checks",
        "MAX_NEAREST_K": "babyrobot_marl.core.checks", "check_batch": "babyrobot_marl.core.checks",
        "MAX_FRAME_PIXELS": "babyrobot_marl.render.checks", "check_frame_pixels": "babyrobot_marl.render.checks",
        "max_cell_size": "babyrobot_marl.render.checks",
    }),
    "babyrobot_marl.encodings": ("babyrobot_marl.envs.encodings", {
        "ENCODINGS": "babyrobot_marl.envs.encodings", "Encoder": "babyrobot_marl.envs.encodings",
        "check_encoding": "babyrobot_marl.envs.checks",
    }),
    "babyrobot_marl.animation": ("babyrobot_marl.play.screen", {
        name: "babyrobot_marl.play.screen"
        for name in ("DEFAULT_DELAY", "Display", "animate", "isatty", "CURSOR_HOME", "CLEAR_SCREEN", "SHOW_CURSOR")
    }),
    "babyrobot_marl.level_files": ("babyrobot_marl.levels.files", {
        "read_level_file": "babyrobot_marl.levels.files", "load_level": "babyrobot_marl.levels.files",
    }),
    "babyrobot_marl.level_sources": ("babyrobot_marl.levels.sources", {
        name: "babyrobot_marl.levels.sources" for name in ("maze_family", "level_source", "LevelSource", "FAMILY_SEEDS")
    }),
    "babyrobot_marl.notebook": ("babyrobot_marl.play.notebook", {
        "play": "babyrobot_marl.play.notebook", "edit": "babyrobot_marl.play.notebook",
    }),
    "babyrobot_marl.envs.common": ("babyrobot_marl.core.outcomes", {
        "OUTCOME_NAMES": "babyrobot_marl.core.outcomes", "START": "babyrobot_marl.core.outcomes",
        "FINISHED": "babyrobot_marl.core.outcomes", "resolve_level": "babyrobot_marl.levels.resolve",
        "resolve_rules": "babyrobot_marl.core.rules", "known_args": "babyrobot_marl.core.rules",
        "unexpected_keyword": "babyrobot_marl.core.checks", "check_seed": "babyrobot_marl.core.checks",
        "check_action": "babyrobot_marl.core.checks", "ACTION_HELP": "babyrobot_marl.core.checks",
        "check_render_mode": "babyrobot_marl.envs.checks", "check_options": "babyrobot_marl.envs.checks",
    }),
    "babyrobot_marl.play.keys": ("babyrobot_marl.envs.keys", {
        name: "babyrobot_marl.envs.keys"
        for name in ("TERMINAL_KEYS", "BROWSER_KEYS", "HELP", "QUIT", "RESTART", "SWITCH", "Command", "decode", "keys_to_action")
    }),
}


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_path_warns_naming_the_new_one_and_gives_the_same_objects(old, monkeypatch):
    new, names = MOVED[old]
    monkeypatch.delitem(sys.modules, old, raising=False)  # imported afresh, so its warning is raised here
    with pytest.warns(DeprecationWarning, match=new.replace(".", r"\.")):
        module = importlib.import_module(old)
    for name, home in names.items():
        assert getattr(module, name) is getattr(importlib.import_module(home), name), name


def test_old_names_that_were_renamed_are_the_new_objects(monkeypatch):
    from babyrobot_marl.core.checks import check_count
    from babyrobot_marl.envs.spec import StepLimitSpec

    monkeypatch.delitem(sys.modules, "babyrobot_marl.envs.common", raising=False)
    with pytest.warns(DeprecationWarning):
        common = importlib.import_module("babyrobot_marl.envs.common")
    assert common.check_positive_int is check_count and common.OwnStepLimitSpec is StepLimitSpec


def test_the_root_still_offers_the_encodings_module_without_a_warning():
    import warnings

    import babyrobot_marl

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert babyrobot_marl.encodings.Encoder is importlib.import_module("babyrobot_marl.envs.encodings").Encoder
