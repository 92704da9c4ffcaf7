"""The import paths that moved before the first release are gone, and the packages that took their
place keep every name they offered.

The old modules (root ``checks``, ``encodings``, ``animation``, ``level_files``, ``level_sources``,
``cli_args``, ``notebook``, and ``envs.common``, ``play.keys``, ``training.cli``) no longer import; the
CHANGELOG says where each went. ``training.ppo``, ``experiments`` and ``cli`` became packages at the
same import path: every name imported from them before is still there, and is the object of the
module that now holds it.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import sys

import pytest

# old path -> where it went (CHANGELOG.md)
GONE = {
    "babyrobot_marl.checks": "babyrobot_marl.core.checks",
    "babyrobot_marl.encodings": "babyrobot_marl.envs.encodings",
    "babyrobot_marl.animation": "babyrobot_marl.play.screen",
    "babyrobot_marl.level_files": "babyrobot_marl.levels.files",
    "babyrobot_marl.level_sources": "babyrobot_marl.levels.sources",
    "babyrobot_marl.cli_args": "babyrobot_marl.cli.checks",
    "babyrobot_marl.notebook": "babyrobot_marl.play.notebook",
    "babyrobot_marl.envs.common": "babyrobot_marl.core.checks",
    "babyrobot_marl.play.keys": "babyrobot_marl.envs.keys",
    "babyrobot_marl.training.cli": "babyrobot_marl.cli.train",
}


@pytest.mark.parametrize("old", sorted(GONE))
def test_an_old_path_is_gone_and_its_new_home_imports(old):
    # looked up in the package's own folders (as an installed package is): an editable install of another
    # checkout may still serve the old file through its own finder
    parent, _, name = old.rpartition(".")
    assert importlib.machinery.PathFinder.find_spec(old, importlib.import_module(parent).__path__) is None, name
    assert importlib.import_module(GONE[old])


def test_the_changelog_says_where_each_old_path_went():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "CHANGELOG.md").read_text(encoding="utf-8")
    for old, new in GONE.items():
        assert f"`{old.removeprefix('babyrobot_marl.')}`" in text, old
        assert f"`{new.removeprefix('babyrobot_marl.')}`" in text, new


def test_the_root_still_offers_the_encodings_module_as_an_attribute():
    import warnings

    import babyrobot_marl

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert babyrobot_marl.encodings.Encoder is importlib.import_module("babyrobot_marl.envs.encodings").Encoder


# What README, docs, examples, benchmarks and tests imported from training.ppo before it became a package
PPO_NAMES = {
    "config": ["PPOConfig", "START_CHOICES"],
    "inputs": ["Inputs", "make_inputs", "near_offsets"],
    "net": ["make_net", "log_softmax", "dense_input", "DENSE_LIMIT"],
    "sampler": ["PerKey", "Sampler", "distinct_rows", "TABLE_LIMIT"],
    "update": ["Samples", "ppo_gradients", "grads_of", "clip_grad_norm"],
    "result": ["EvalPoint", "TrainResult"],
    "loop": ["train_ppo", "make_batch", "torch_threads"],
}


def test_training_ppo_keeps_every_name_and_each_is_its_modules_object():
    ppo = importlib.import_module("babyrobot_marl.training.ppo")
    for module, names in PPO_NAMES.items():
        sub = importlib.import_module(f"babyrobot_marl.training.ppo.{module}")
        for name in names:
            assert getattr(ppo, name) is getattr(sub, name), name
    checks = importlib.import_module("babyrobot_marl.training.checks")
    assert ppo.TrainingDivergedError is checks.TrainingDivergedError and ppo.check_finite is checks.check_finite
    assert ppo.MAX_NEAR_RADIUS is checks.MAX_NEAR_RADIUS == 4
    assert issubclass(ppo.TrainingDivergedError, ValueError)


def test_experiments_and_cli_keep_their_names():
    experiments = importlib.import_module("babyrobot_marl.experiments")
    stats, races = (importlib.import_module(f"babyrobot_marl.experiments.{m}") for m in ("stats", "races"))
    for name in ("Z95", "Metric", "mean_interval", "wilson"):
        assert getattr(experiments, name) is getattr(stats, name)
    for name in ("RaceRecord", "RaceStats", "run_races", "summary"):
        assert getattr(experiments, name) is getattr(races, name)
    cli = importlib.import_module("babyrobot_marl.cli")
    entry = importlib.import_module("babyrobot_marl.cli.entry")
    assert cli.main is entry.main and cli.build_parser is entry.build_parser and callable(cli.main)


def test_the_cli_takes_nothing_from_the_package_root():
    """``--version`` reads the installed distribution's metadata: every ``from <root> import x`` of the CLI's
    modules names a module or subpackage, never an attribute of the root's ``__init__`` (``__version__``)."""
    import ast
    from pathlib import Path

    cli = importlib.import_module("babyrobot_marl.cli")
    pkg_dir = Path(importlib.import_module("babyrobot_marl").__file__).parent
    files = sorted(Path(cli.__file__).parent.glob("*.py")) if cli.__file__.endswith("__init__.py") else [Path(cli.__file__)]
    for path in files:
        package = "babyrobot_marl.cli" if path.parent != pkg_dir else "babyrobot_marl"
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.ImportFrom):
                continue
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module
            if target == "babyrobot_marl":
                for alias in node.names:
                    name = alias.name
                    assert (pkg_dir / f"{name}.py").exists() or (pkg_dir / name).is_dir(), f"{path.name}: {name}"
    assert importlib.import_module("babyrobot_marl").__version__ in " ".join(_version_line().split())


def _version_line() -> str:
    import subprocess

    done = subprocess.run([sys.executable, "-m", "babyrobot_marl", "--version"], capture_output=True, text=True, timeout=300)
    return done.stdout
