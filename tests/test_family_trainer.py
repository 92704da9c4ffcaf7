"""The fast trainer on level families (issue 27 item 3): an atlas of mazes on the batch engine, the net reading
local windows and the goal hint, the same input as race_v0's observe="local" rows, saved and run on the env."""

import numpy as np
import pytest

pytest.importorskip("torch")

from babyrobot_marl import race_v0  # noqa: E402
from babyrobot_marl.core.batch import BatchRace  # noqa: E402
from babyrobot_marl.core.rules import Rules  # noqa: E402
from babyrobot_marl.core.table import compile_level  # noqa: E402
from babyrobot_marl.levels import builtin  # noqa: E402
from babyrobot_marl.training.policy import WindowPolicy, load_checkpoint, load_policy  # noqa: E402
from babyrobot_marl.training.ppo import PPOConfig, train_ppo  # noqa: E402
from babyrobot_marl.training.ppo.inputs import near_offsets  # noqa: E402
from babyrobot_marl.training.ppo.window import (  # noqa: E402
    NO_ACTION,
    Atlas,
    WindowForm,
    play_atlas,
    stack_levels,
    unique_rows,
)

SMALL = PPOConfig(n_envs=32, n_steps=8, batch_size=1024, atlas_size=4, atlas_every=2, eval_every=0)


@pytest.fixture(scope="module")
def trained():
    return train_ppo("maze:8..10", n_robots=3, timesteps=20_000, seed=0, config=SMALL.replace(hint=True))


def test_stacked_levels_compile_to_each_levels_moves():
    levels = [builtin.get("maze-8x8-s1"), builtin.get("maze-10x10-s2"), builtin.get("maze-9x9-s3")]
    stacked, tops = stack_levels(levels)
    table = compile_level(stacked)
    for lv, top in zip(levels, tops.tolist()):
        t = compile_level(lv)
        ids = (top + np.arange(lv.n_cells) // lv.width) * stacked.width + np.arange(lv.n_cells) % lv.width
        assert (table.target[ids] == ids[t.target]).all()  # every move stays inside its own maze
        assert (table.is_exit[ids] == t.is_exit).all()


def test_window_patterns_are_numbered_as_numpys_unique_rows():
    rng = np.random.default_rng(0)
    for rows in (rng.integers(0, 4, (500, 7)), rng.integers(0, 70_000, (50, 3)), rng.integers(-2, 3, (40, 2)),
                 np.zeros((0, 4), dtype=np.int64), np.array([[300, 1], [2, 299], [300, 1], [2, 256]])):
        want, want_inv = np.unique(rows, axis=0, return_inverse=True)
        got, got_inv = unique_rows(rows)
        assert np.array_equal(got, want) and np.array_equal(got_inv, want_inv.reshape(-1))


def test_atlas_resets_put_each_env_on_one_maze():
    levels = [builtin.get("maze-8x8-s1"), builtin.get("maze-12x12-s2")]
    atlas = Atlas(levels, Rules(), WindowForm(2, near_offsets(1), False))
    batch = atlas.batch(200, 4, 300)
    batch.reset_drawn(np.arange(200), np.random.default_rng(0))
    rows = batch.cells // atlas.level.width
    maze = (rows >= 9).astype(int)  # maze 1 starts at row 9 (8 rows, one blocked row)
    assert (maze == maze[:, :1]).all() and set(maze[:, 0]) == {0, 1}
    assert (maze[:, 0] == batch.pool).all()
    assert all(len(set(r)) == 4 for r in batch.cells.tolist())  # distinct starts


def test_reset_drawn_is_the_same_for_the_same_generator_and_covers_the_free_cells():
    t = compile_level(builtin.get("maze-8x8-s1"))
    a = BatchRace(t, 500, 2, 100, (), t.free_cells, "random")
    b = BatchRace(t, 500, 2, 100, (), t.free_cells, "random")
    a.reset_drawn(np.arange(500), np.random.default_rng(7))
    b.reset_drawn(np.arange(500), np.random.default_rng(7))
    assert (a.cells == b.cells).all() and (a.keys == b.keys).all()
    assert set(a.cells.ravel().tolist()) == set(t.free_cells)
    assert (a.cells[:, 0] != a.cells[:, 1]).all()


def test_the_trainer_and_the_env_see_the_same_input_and_act_the_same(trained):
    """Rows built from the batch engine's cells equal rows read from race_v0's observe='local', hint=True
    observations, and the trained policy's actions from both are equal, over whole races."""
    form = WindowForm(2, near_offsets(SMALL.near_radius), True)
    env = race_v0.parallel_env(level="maze:8..10", n_robots=3, observe="local", hint=True, start="random")
    policy = trained.policy().for_env(env)
    rng = np.random.default_rng(1)
    checked = 0
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        atlas = Atlas([env.level], env.rules, form)
        while env.agents:
            cells = np.array(env._cells)[None, :]
            racing = np.array(env._racing)[None, :]
            batch_rows = atlas.rows(atlas.keys(cells, racing))
            for a in env.agents:
                i = env.possible_agents.index(a)
                assert (policy.rows(obs[a])[0] == batch_rows[i]).all()
                probs = trained.net.actor(__import__("torch").from_numpy(batch_rows[i : i + 1])).argmax().item()
                assert policy(obs[a]) == probs
                checked += 1
            obs, *_ = env.step({a: int(rng.integers(5)) for a in env.agents})
    assert checked > 100


@pytest.fixture(scope="module")
def trained_memory():
    return train_ppo("maze:8..10", n_robots=3, timesteps=20_000, seed=0, config=SMALL.replace(memory=True))


def test_with_memory_each_robot_reads_its_last_action_as_the_trainer_did(trained_memory):
    """With ``memory`` the net also reads the robot's last action (none at the episode's start): rows built
    from the batch engine's cells and last actions equal the rows each robot's own bound policy reads from
    race_v0's observations over whole races, and the actions agree."""
    import torch

    form = WindowForm(2, near_offsets(SMALL.near_radius), False, memory=True)
    env = race_v0.parallel_env(level="maze:8..10", n_robots=3, observe="local", start="random", max_cycles=60)
    checked, lasts = 0, set()
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        robots = {a: trained_memory.policy().for_env(env) for a in env.possible_agents}  # one each, fresh memory
        atlas = Atlas([env.level], env.rules, form)
        last = np.full((1, 3), NO_ACTION)
        while env.agents:
            cells, racing = np.array(env._cells)[None, :], np.array(env._racing)[None, :]
            batch_rows = atlas.rows(atlas.keys(cells, racing, last))
            actions = {}
            for a in env.agents:
                i = env.possible_agents.index(a)
                assert robots[a].last == last[0, i]
                assert (robots[a].rows(obs[a])[0] == batch_rows[i]).all()
                actions[a] = robots[a](obs[a])
                assert actions[a] == trained_memory.net.actor(torch.from_numpy(batch_rows[i : i + 1])).argmax().item()
                last[0, i] = actions[a]
                lasts.add(int(last[0, i]))
                checked += 1
            obs, *_ = env.step(actions)
    assert checked > 100 and len(lasts) > 1
    # the last action is its own input unit: two robots on one cell that came by different moves read different rows
    keys = atlas.keys(np.array([[0, 0]]), np.array([[True, True]]), np.array([[1, 2]]))
    a, b = atlas.rows(keys)
    assert (a != b).sum() == 1 and form.n_in == form.n_static + len(form.near) + 5


def test_memory_is_for_level_families_and_saved_with_the_policy(trained_memory, tmp_path):
    with pytest.raises(ValueError, match="^memory: the last-action input is read by a level family's policy"):
        train_ppo("maze-8x8", timesteps=10, config=SMALL.replace(memory=True))
    with pytest.raises(ValueError, match="^memory: must be True or False"):
        PPOConfig(memory=1)
    policy = load_policy(trained_memory.save(str(tmp_path / "m.pt")))
    assert isinstance(policy, WindowPolicy) and policy.form.memory
    env = race_v0.parallel_env(level="maze:8..8", n_robots=3, observe="local", start="random")
    bound = policy.for_env(env)
    obs, _ = env.reset(seed=0)
    action = bound(obs["robot_0"])
    assert bound.last == action and policy.last == NO_ACTION and policy.for_env(env).last == NO_ACTION


def test_a_family_policy_saves_its_observation_form_and_runs_on_the_env(trained, tmp_path):
    path = trained.save(str(tmp_path / "p.pt"))
    data = load_checkpoint(path)
    assert data["observation"] == {"observe": "local", "obs_encoding": "multidiscrete", "view_radius": 2, "hint": True}
    env = race_v0.parallel_env(level="maze:12..12", n_robots=3, observe="local", hint=True, start="random")
    policy = load_policy(path, env=env)
    assert isinstance(policy, WindowPolicy) and policy.observation == {"observe": "local", "view_radius": 2, "hint": True}
    obs, _ = env.reset(seed=0)
    assert all(0 <= policy(obs[a]) < 5 for a in env.agents)
    for wrong in ({"hint": False}, {"view_radius": 1}):
        other = race_v0.parallel_env(level="maze:12..12", n_robots=3, observe="local", start="random",
                                     **{"hint": True, **wrong})
        with pytest.raises(ValueError, match="policy: trained on observe='local', view_radius=2, hint=True"):
            load_policy(path, env=other)


def test_the_hint_policy_learns_to_reach_exits_of_unseen_mazes():
    """With the goal hint, a short run already beats random walking by far on mazes of the evaluation seeds."""
    from babyrobot_marl.levels.sources import EVAL_MAZE_SEEDS, parse_level_family
    from babyrobot_marl.training.ppo.window import Family

    result = train_ppo("maze:8..8", n_robots=2, timesteps=1_000_000, seed=0,
                       config=PPOConfig(n_envs=256, batch_size=8192, hint=True, atlas_size=16, eval_every=0))
    fam = Family(parse_level_family("maze:8..8", EVAL_MAZE_SEEDS), 2, result.config, 5, {})
    score = play_atlas(result.net, fam.atlas(16), 2, 100, fam.max_steps, np.random.default_rng(0))
    assert score["success_rate"] >= 0.9


def test_files_of_format_3_still_load_and_a_bad_observation_form_is_refused(trained, tmp_path):
    import torch

    from babyrobot_marl.training.policy import TrainedPolicy

    old = train_ppo("race-2", 2, 512, seed=0, config=PPOConfig(n_envs=16, n_steps=16, batch_size=128, eval_every=0))
    path = old.save(str(tmp_path / "old.pt"))
    data = torch.load(path, weights_only=True)
    data.update(version=3, observation={"observe": "global", "obs_encoding": "multidiscrete"})
    torch.save(data, path)
    assert isinstance(load_policy(path), TrainedPolicy)
    family = torch.load(trained.save(str(tmp_path / "f.pt")), weights_only=True)
    family["observation"]["view_radius"] = -1
    torch.save(family, tmp_path / "bad.pt")
    with pytest.raises(ValueError, match=r"broken policy file: observation: this version reads policies of"):
        load_policy(tmp_path / "bad.pt")


def test_blocked_cost_lowers_the_training_reward_of_blocked_steps_only(monkeypatch):
    from babyrobot_marl.training.ppo import loop
    from babyrobot_marl.training.ppo.update import gae

    seen: list[np.ndarray] = []

    def spy(rewards, *args):  # the rewards the advantages are computed from
        seen.append(rewards.copy())
        return gae(rewards, *args)

    monkeypatch.setattr(loop, "gae", spy)
    cfg = SMALL.replace(hint=True, n_envs=16)
    returns = []
    for cost in (0.0, 0.75):
        train_ppo("maze:8..8", n_robots=8, timesteps=1, seed=3, config=cfg.replace(blocked_cost=cost),
                  env_kwargs={"collisions": "bounce"}, on_update=lambda t, s, r: returns.append(r))
    plain, costed = seen
    diff = np.round(plain - costed, 6)  # the same seed: the same first rollout, only the rewards differ
    assert set(np.unique(diff).tolist()) == {0.0, 0.75}
    assert returns[0] == returns[1]  # the returns reported are the env's


def test_blocked_cost_must_be_a_non_negative_number():
    with pytest.raises(ValueError, match="blocked_cost"):
        PPOConfig(blocked_cost=-1.0)


@pytest.mark.parametrize("n_robots", [2, 4, 16, 17])
def test_a_robots_near_code_has_a_bit_for_each_racing_robot_on_its_near_cells(n_robots):
    """Up to PAIRWISE_ROBOTS robots by every pair's offset, more by sorting cells: both as a loop over robots says."""
    levels = [builtin.get("maze-8x8-s1"), builtin.get("maze-12x12-s2")]
    near = near_offsets(2)
    atlas = Atlas(levels, Rules(), WindowForm(2, near, False))
    batch = atlas.batch(40, n_robots, 300)
    rng = np.random.default_rng(n_robots)
    batch.reset_drawn(np.arange(40), rng)
    for _ in range(3):
        racing = rng.random(batch.cells.shape) < 0.8
        code = atlas.near_code(batch.cells, racing)
        w = atlas.level.width
        for e in range(40):
            for i in range(n_robots):
                xi, yi = batch.cells[e, i] % w, batch.cells[e, i] // w
                want = 0
                for j in range(n_robots):
                    offset = (batch.cells[e, j] % w - xi, batch.cells[e, j] // w - yi)
                    if j != i and racing[e, j] and offset in near:
                        want |= 1 << near.index(offset)
                assert code[e, i] == want, (e, i)
        batch.step(rng.integers(0, 5, batch.cells.shape))
