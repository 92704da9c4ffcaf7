"""Every script of ``examples/`` runs with its smallest settings (issue 23).

Each runs as a reader runs it (``python examples/NAME.py ...``) in a temporary folder, so the files
it writes stay out of the checkout. A script needing an extra skips only when that extra is missing,
saying "needs the ... extra"; CI's train venv runs them all. ``rllib_race.py`` runs in
``.ci/rllib.sh`` (the rllib venv; ray[rllib] pins gymnasium 1.2.2), ``readme_pictures.py`` in
``tests/test_clean_runs.py`` (in a fresh copy of the checkout: it must redraw the committed pictures).
"""

from __future__ import annotations

import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

# script: (its smallest arguments, the extra it needs (module), a line its output must have)
SMALLEST = {
    "q_learning.py": (["--level", "default", "--episodes", "200"], None, r"^SARSA +200 episodes"),
    "train_fast.py": (["--steps", "20000"], ("train", "torch"), r"^replayed the saved policy: return "),
    "train_ppo.py": (["--steps", "2000"], ("train", "stable_baselines3"), r"^saved babyrobot_ppo_maze-8x8\.zip and "),
    "train_race.py": (
        ["--level", "race-2", "--robots", "2", "--steps", "2000", "--races", "5"],
        ("train", "supersuit"),
        r"^saved babyrobot_race_race-2\.zip$",
    ),
}
# scripts another CI step runs with their smallest settings: in a venv of their own, or in a test that
# checks what they draw (the README pictures take seconds: one run is enough)
ELSEWHERE = {"rllib_race.py": ".ci/rllib.sh", "readme_pictures.py": "tests/test_clean_runs.py"}


def test_every_example_runs_in_ci():
    assert sorted(p.name for p in EXAMPLES.glob("*.py")) == sorted([*SMALLEST, *ELSEWHERE])
    for name, script in ELSEWHERE.items():
        text = (ROOT / script).read_text(encoding="utf-8")
        assert re.search(rf"examples/{re.escape(name)}(?![\w.])", text), f"{script} does not run examples/{name}"


def _trains(name: str) -> bool:
    return SMALLEST[name][1] is not None and SMALLEST[name][1][0] == "train"


@pytest.mark.parametrize("name", [pytest.param(n, marks=[pytest.mark.train] * _trains(n)) for n in sorted(SMALLEST)])
def test_example_runs_with_its_smallest_settings(name, tmp_path):
    args, needs, claim = SMALLEST[name]
    if needs and importlib.util.find_spec(needs[1]) is None:
        pytest.skip(f"examples/{name} needs the {needs[0]} extra ({needs[1]} not installed)")
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
        "OMP_NUM_THREADS": "1",  # torch on one thread, as the package's trainers run it on a busy machine
    }
    # a guard against a hang, not a speed target
    got = subprocess.run(
        [sys.executable, str(EXAMPLES / name), *args], capture_output=True, text=True, cwd=tmp_path, env=env, timeout=1800
    )
    assert got.returncode == 0, f"examples/{name} {' '.join(args)} exited {got.returncode}:\n{got.stderr[-3000:]}"
    assert re.search(claim, got.stdout, re.M), f"examples/{name} printed:\n{got.stdout[-3000:]}"
