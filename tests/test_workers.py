"""A fresh worker process knows the env ids only through the ``"module:id"`` form.

Ray actors, rl_games' workers and ``multiprocessing`` "spawn" children start a new interpreter:
the ids that ``import babyrobot_marl`` registered in the driver are not there.
``gymnasium.make("babyrobot_marl:babyrobot_marl/BabyRobot-v0")`` imports the package first
(docs/guides/other-libraries.md, "Running on workers").

This module must not import ``babyrobot_marl`` at its top: a spawn worker imports it to find
``in_worker``, and the point is that the worker's code knows only the id string.
"""

from __future__ import annotations

import multiprocessing
import re
import sys
from pathlib import Path
from typing import Any

import gymnasium
from gymnasium.wrappers import TimeAwareObservation

MODULE_ID = "babyrobot_marl:babyrobot_marl/BabyRobot-v0"
PLAIN_ID = "babyrobot_marl/BabyRobot-v0"
DOC = Path(__file__).resolve().parents[1] / "docs" / "guides" / "other-libraries.md"
# a worker imports numpy, gymnasium and the package: seconds on a loaded machine; this only bounds a hang
WAIT = 600


def in_worker(seed: int) -> dict[str, Any]:
    """Runs in the spawn worker: what it knew before ``make``, then one episode of the made env."""
    out: dict[str, Any] = {"imported_before": "babyrobot_marl" in sys.modules, "known_before": PLAIN_ID in gymnasium.registry}
    try:
        gymnasium.make(PLAIN_ID)
    except gymnasium.error.Error as err:  # NamespaceNotFound: the plain id needs the import
        out["plain_id_error"] = type(err).__name__
    env = TimeAwareObservation(gymnasium.make(MODULE_ID, level="puddles"))
    out["cells"], out["times"] = episode(env, seed)
    out["max_episode_steps"] = env.spec.max_episode_steps
    return out


def episode(env, seed: int) -> tuple[list[list[int]], list[int]]:
    """The robot's cells and the time-aware observation's clock, random actions from a seeded space."""
    _, info = env.reset(seed=seed)
    env.action_space.seed(seed)
    cells, times = [info["cell"].tolist()], []
    while True:
        obs, _, terminated, truncated, info = env.step(env.action_space.sample())
        cells.append(info["cell"].tolist())
        times.append(int(obs[-1]))
        if terminated or truncated:
            return cells, times


def test_a_spawn_worker_that_only_knows_the_id_string_makes_and_steps_the_env():
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        got = pool.apply_async(in_worker, (3,)).get(timeout=WAIT)
    assert got["imported_before"] is False and got["known_before"] is False  # a fresh process indeed
    assert got["plain_id_error"] == "NamespaceNotFound"  # what a worker sees without the module
    import babyrobot_marl  # noqa: F401  (here, in the test process: the same episode, seeded the same)

    env = TimeAwareObservation(gymnasium.make(PLAIN_ID, level="puddles"))
    assert (got["cells"], got["times"]) == episode(env, 3)
    assert got["times"] == list(range(1, len(got["times"]) + 1))
    assert got["max_episode_steps"] == env.spec.max_episode_steps == 100


def test_async_vector_env_with_spawn_workers_from_the_module_id():
    envs = gymnasium.make_vec(MODULE_ID, num_envs=2, vectorization_mode="async", vector_kwargs={"context": "spawn"})
    try:
        obs, _ = envs.reset(seed=0)
        for _ in range(5):
            obs, *_ = envs.step(envs.action_space.sample())
        assert obs.shape == (2, 2)
    finally:
        envs.close()


def test_the_running_on_workers_note_names_the_module_id_form():
    text = DOC.read_text(encoding="utf-8")
    match = re.search(r"^## Running on workers\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    assert match, "docs/guides/other-libraries.md has no 'Running on workers' section"
    section = match.group(1)
    for name in ("Ray", "rl_games", '"spawn"', MODULE_ID):
        assert name in section
    assert "```python" in section  # a block that test_docs_blocks runs
