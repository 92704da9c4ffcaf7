"""Issue 25, the upper layers: the moved modules' old import paths keep working for one release.

``cli_args`` and ``training/cli`` are shims: importing them warns (``DeprecationWarning`` naming the new
path) and gives the very objects of the new modules. ``training.ppo``, ``experiments`` and ``cli`` became
packages at the same import path: every name imported from them before the move is still there, and is
the object of the module that now holds it.
"""

from __future__ import annotations

import importlib
import sys

import pytest

SHIMS = {
    "babyrobot_marl.cli_args": ("babyrobot_marl.cli.checks", {
        name: name for name in ("MAX_RACES", "int_at_least", "int_in", "non_negative_float", "non_negative_int", "output_path",
                                "policy_list", "policy_spec", "positive_float", "positive_int", "probability", "race_count",
                                "seconds", "unit_real")
    }),
    "babyrobot_marl.training.cli": ("babyrobot_marl.cli.train", {
        "add_train_parser": "add_parser", "cmd_train": "run", "BACKENDS": "BACKENDS", "KNOBS": "KNOBS",
        "FAST_ROLLOUT": "FAST_ROLLOUT", "SB3_ROLLOUT": "SB3_ROLLOUT", "SB3_RACE_ROLLOUT": "SB3_RACE_ROLLOUT",
        "RACE_TARGET": "RACE_TARGET",
    }),
}


@pytest.mark.parametrize("old", sorted(SHIMS))
def test_a_shim_warns_naming_the_new_path_and_gives_the_same_objects(old, monkeypatch):
    new, names = SHIMS[old]
    monkeypatch.delitem(sys.modules, old, raising=False)  # a fresh import: the warning comes at import time
    with pytest.warns(DeprecationWarning, match=new.replace(".", r"\.")):
        shim = importlib.import_module(old)
    target = importlib.import_module(new)
    for old_name, new_name in names.items():
        assert getattr(shim, old_name) is getattr(target, new_name), old_name


def test_nothing_in_the_package_imports_the_upper_shims():
    code = ("import warnings; warnings.simplefilter('error', DeprecationWarning); "
            "import babyrobot_marl.cli, babyrobot_marl.experiments, babyrobot_marl.training.ppo, babyrobot_marl.training.policy")
    import subprocess

    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr


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
