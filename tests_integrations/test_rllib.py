"""RLlib (the venv of .ci/rllib.sh: ray[rllib] pins gymnasium 1.2.2): its own PettingZoo wrapper and default
encoder on the one-hot race, one PPO iteration."""

from __future__ import annotations

import ast

from conftest import readme_has


def test_readme_shows_the_rllib_snippet_this_test_runs():
    assert readme_has("rllib_snippet")


def test_rllib_ppo_trains_one_iteration_with_its_default_encoder_on_the_onehot_race(snippet):
    last = snippet("rllib_snippet").strip().splitlines()[-1]
    returns = ast.literal_eval(last.replace("np.float64(", "(").replace("np.float32(", "("))
    assert sorted(returns) == [f"robot_{i}" for i in range(4)] and all(r < 0 for r in returns.values())
