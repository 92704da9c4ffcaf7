"""AgileRL (own venv: it pins pettingzoo < 1.27 and tensordict 0.13): IPPO on the race, both finished modes."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from agilerl.vector.pz_async_vec_env import AsyncPettingZooVecEnv
from conftest import SNIPPETS, readme_has

from babyrobot_marl import race_v0


def test_readme_shows_the_agilerl_snippet_this_test_runs():
    assert readme_has("agilerl_snippet")


def test_agilerl_ippo_trains_on_the_frozen_race(snippet):
    fitnesses = snippet("agilerl_snippet").strip().splitlines()[-1]
    assert fitnesses.startswith("[") and "nan" not in fitnesses


def test_agilerl_vector_env_steps_the_removing_race_with_actions_for_every_possible_agent():
    """AgileRL sends an action for every possible agent: robots that have finished are ignored, races end and restart."""
    kwargs = dict(level="race-4", n_robots=4, finished="remove", max_cycles=30, obs_encoding="onehot")
    env = AsyncPettingZooVecEnv([lambda: race_v0.parallel_env(**kwargs) for _ in range(2)])
    try:
        env.reset(seed=0)
        rng, finishes = np.random.default_rng(0), 0
        for _ in range(120):
            actions = {a: rng.integers(0, 5, 2) for a in env.possible_agents}
            _, _, terms, _, infos = env.step(actions)
            finishes += int(sum(np.nansum(terms[a]) for a in env.possible_agents))
        assert finishes > 0
    finally:
        env.close()


AGILERL_NAN = "AgileRL feeds NaN placeholder observations of agents that have left to IPPO's actor"


@pytest.mark.xfail(raises=AssertionError, strict=True, reason=AGILERL_NAN)
def test_agilerl_ippo_on_the_removing_race_fails_inside_agilerl(tmp_path):
    src = (SNIPPETS / "agilerl_snippet.py").read_text().replace('finished="freeze"', 'finished="remove"')
    # AgileRL's nets and samples draw from the global generators: seeded, the run is the same every time
    # (unseeded, a run whose sampled actions never fed a left agent's placeholder passed now and then)
    src = "import random, numpy, torch\nrandom.seed(0); numpy.random.seed(0); torch.manual_seed(0)\n" + src
    (tmp_path / "agilerl_remove.py").write_text(src)
    proc = subprocess.run([sys.executable, "agilerl_remove.py"], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
