"""The fast trainer with own goals (goals="own", soft collisions, lifelong): the net reads each robot's target
channel and the hint toward its own target, the same rows race_v0 shows a bound policy; settings saved with
the policy, checked by name."""

import numpy as np
import pytest

pytest.importorskip("torch")

from babyrobot_marl import race_v0  # noqa: E402
from babyrobot_marl.core.level import Level  # noqa: E402
from babyrobot_marl.training.policy import load_checkpoint, load_policy  # noqa: E402
from babyrobot_marl.training.ppo import PPOConfig, train_ppo  # noqa: E402
from babyrobot_marl.training.ppo.goal_inputs import closed_edges  # noqa: E402
from babyrobot_marl.training.ppo.inputs import near_offsets  # noqa: E402
from babyrobot_marl.training.ppo.window import Atlas, WindowForm  # noqa: E402

SMALL = PPOConfig(n_envs=32, n_steps=8, batch_size=1024, atlas_size=4, atlas_every=2, eval_every=0, hint=True)
OWN = {"goals": "own", "collisions": "soft"}
GRID = "\n".join([".....#....", ".##..#.##.", ".#.......#", ".#.##.#...", "......#.#.", "##.#....#.",
                  "...#.##...", ".#...#..#.", ".#.#...##.", "...#.#...."])


@pytest.fixture(scope="module")
def trained():
    return train_ppo("maze:8..10", n_robots=4, timesteps=20_000, seed=0, config=SMALL, env_kwargs=OWN)


def _goal_cells(env) -> np.ndarray:
    w = env.level.width
    return np.array([[env.goals[a][1] * w + env.goals[a][0] for a in env.possible_agents]])


@pytest.mark.parametrize("level, lifelong", [("maze:8..10", False), (Level.from_grid(GRID), False),
                                             (Level.from_grid(GRID), True)])
def test_the_trainer_reads_the_rows_race_v0_shows_a_bound_robot_with_own_goals(trained, level, lifelong):
    """Rows built from the batch engine's cells and goals equal the rows the bound policy reads from race_v0's
    observe='local', hint=True, goals='own' observations (target channel, hint toward its own goal), on the
    package's mazes and on a grid map of blocked cells, lifelong too; the actions from both agree."""
    import torch

    form = WindowForm(2, near_offsets(SMALL.near_radius), True, goals="own")
    env = race_v0.parallel_env(level=level, n_robots=4, observe="local", hint=True, start="random", max_cycles=60,
                               lifelong=lifelong, **OWN)
    policy = trained.policy().for_env(env)
    rng = np.random.default_rng(1)
    checked, targets = 0, set()
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        atlas = Atlas([env.level], env.rules, form, lifelong)
        while env.agents:
            cells, racing = np.array(env._cells)[None, :], np.array(env._racing)[None, :]
            goals = _goal_cells(env)
            targets.update(goals.ravel().tolist())
            batch_rows = atlas.rows(atlas.keys(cells, racing, None, goals))
            for a in env.agents:
                i = env.possible_agents.index(a)
                assert (policy.rows(obs[a])[0] == batch_rows[i]).all()
                assert policy(obs[a]) == trained.net.actor(torch.from_numpy(batch_rows[i : i + 1])).argmax().item()
                checked += 1
            obs, *_ = env.step({a: int(rng.integers(5)) for a in env.agents})
    assert checked > 200 and len(targets) >= 12 + lifelong  # lifelong: new targets on the way


def test_the_hint_is_the_one_toward_the_robots_own_target():
    """Two robots on one cell with different targets read different hints (and target cells): the key holds them."""
    level = Level.from_grid(GRID)
    atlas = Atlas([level], race_v0.parallel_env(level=level, goals="own", start="random").rules,
                  WindowForm(2, (), True, goals="own"))
    w = level.width
    a, b = atlas.rows(atlas.keys(np.array([[0, 0]]), np.array([[True, True]]), None, np.array([[4, 9 * w]])))
    form = atlas.form
    hint_a, hint_b = (set(r[r >= form.n_static + form.n_window].tolist()) - {form.n_in} for r in (a, b))
    assert hint_a == {form.n_static + form.n_window + 2} and hint_b == {form.n_static + form.n_window + 3}  # EAST, SOUTH


def test_blocked_cells_and_walls_read_alike():
    """A free cell next to a blocked one reads a wall on that side: a grid map looks like a walled maze."""
    feats = np.zeros((1, 9, 6), dtype=np.int64)
    feats[0, 5, 0] = 3  # the cell east of the centre is blocked
    closed = closed_edges(feats, 1)
    assert closed[0, 4, 3] == 1 and closed[0, 4, 2] == 0  # the centre's east side: a wall; north open
    assert (closed[0, 5, 2:] == 1).all()  # the blocked cell: walls all round
    assert closed[0, 2, 4] == 1  # the cell north of it: its south side
    assert (feats[0, 4, 2:] == 0).all()  # a copy


def test_own_goals_need_local_windows():
    with pytest.raises(ValueError, match="^goals: "):
        train_ppo("maze-8x8", n_robots=2, timesteps=1000, config=SMALL, env_kwargs=OWN)


def test_a_policy_of_own_goals_saves_its_settings_and_refuses_an_env_of_exits(trained, tmp_path):
    path = trained.save(str(tmp_path / "own.pt"))
    data = load_checkpoint(path)
    assert data["env"] == {"goals": "own", "collisions": "soft", "lifelong": False, "finished": "remove"}
    exits = race_v0.parallel_env(level="maze:8..10", n_robots=4, observe="local", hint=True, start="random")
    with pytest.raises(ValueError, match=r"^policy: trained with goals='own'; this env has goals='exit'"):
        load_policy(path, env=exits)
    env = race_v0.parallel_env(level="maze:8..10", n_robots=4, observe="local", hint=True, start="random", **OWN)
    obs, _ = env.reset(seed=0)
    assert load_policy(path, env=env)(obs["robot_0"]) in range(5)


# ---------------------------------------------------------------------------- the command line
CLI_SMALL = ["--n-envs", "16", "--n-steps", "16", "--batch-size", "256", "--no-progress"]


@pytest.mark.parametrize("argv, first", [
    (["--lifelong"], "--lifelong: "),
    (["--goals", "own"], "--goals own: "),  # the global rows have no target channel
    (["--goals", "own", "--backend", "sb3"], "--goals own: "),
    (["--observe", "local", "--level", GRID.replace("\n", "\\n")], "--level: "),  # a grid map has no exit
])
def test_train_refuses_goal_flags_by_name_before_training(argv, first, capsys, monkeypatch):
    from babyrobot_marl.training.ppo import loop
    from tests.cli_run import run

    monkeypatch.setattr(loop, "train_ppo", lambda *a, **k: pytest.fail("training started"))
    argv = [a.replace("\\n", "\n") for a in argv]  # a later --level replaces the first
    assert run(["train", "--level", "maze-8x8", "--robots", "4", "--steps", "1000", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"babyrobot-marl: error: {first}") and err.count("\n") == 1, err


def test_a_short_own_goals_run_saves_its_settings_and_evaluates_with_own_goals(tmp_path, capsys):
    import json

    from tests.cli_run import run

    path = tmp_path / "own.pt"
    argv = ["train", "--level", "maze:8..10", "--robots", "4", "--observe", "local", "--hint", "--goals", "own",
            "--collisions", "soft", "--steps", "4096", "--episodes", "16", "--save", str(path), *CLI_SMALL]
    assert run(argv) == 0
    out = capsys.readouterr().out
    assert "own goals, collisions soft" in out and json.loads(out.splitlines()[-1])["timesteps"] >= 4096
    data = load_checkpoint(str(path))
    assert data["env"] == {"goals": "own", "collisions": "soft", "lifelong": False, "finished": "remove"}
    assert data["observation"]["goals"] == "own"
    assert run(["evaluate", str(path), "--level", "maze:8..10", "--robots", "4", "--episodes", "4", "--goals", "own",
                "--collisions", "soft"]) == 0
    figures = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert 0 <= figures["policy"]["success_rate"] <= 1
    # without --goals, a saved policy is evaluated on the task it learnt
    assert run(["evaluate", str(path), "--level", "maze:8..10", "--robots", "4", "--episodes", "4",
                "--collisions", "soft"]) == 0
    assert json.loads(capsys.readouterr().out.splitlines()[-1]) == figures  # the same episodes as with --goals own
    assert run(["evaluate", str(path), "--level", "maze:8..10", "--robots", "4", "--episodes", "4", "--goals", "exit"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "goals" in err and "own" in err  # a policy of own goals in a race to the exits


def test_lifelong_atlases_give_new_targets_and_the_hint_leads_to_them():
    """Robots that follow the trainer's hint toward their own targets reach them; lifelong, each then gets a new
    target and keeps going (nobody finishes), and play_atlas reports targets reached per step."""
    from babyrobot_marl.levels import builtin

    levels = [builtin.get("maze-8x8-s1"), builtin.get("maze-10x10-s2")]
    rules = race_v0.parallel_env(level=levels[0], goals="own", start="random", collisions="pass").rules  # no jams
    atlas = Atlas(levels, rules, WindowForm(2, (), True, goals="own"), lifelong=True)
    batch = atlas.batch(20, 2, 200)
    batch.reset_drawn(np.arange(20), np.random.default_rng(0))
    first = batch.goals.copy()
    for _ in range(200):
        hint = atlas.distances.hint_values(batch.cells, batch.goals)
        moves = np.where(hint > 0, np.log2(hint & -hint).astype(np.int64), 0)  # the lowest optimal action
        batch.step(moves)
    assert batch.reached.min() >= 2 and (batch.goals != first).any() and batch.racing.all()

