"""A robot's trail (``PPOConfig.trail``, ``--trail``): the order in which it stood on the cells next to it, kept
by the trainer beside the batch engine's cells and by each bound policy for its robot, read as the same rows."""

from itertools import product
from types import SimpleNamespace

import numpy as np
import pytest

from babyrobot_marl.training.ppo.trail import (
    KINDS,
    NEVER,
    NO_MOVE,
    OLDEST,
    STILL,
    TRAIL_VALUES,
    Trails,
    neighbours,
    trail_kinds,
    trail_values,
)

torch = pytest.importorskip("torch")

from babyrobot_marl import race_v0  # noqa: E402
from babyrobot_marl.training.policy import load_policy  # noqa: E402
from babyrobot_marl.training.ppo import PPOConfig, train_ppo  # noqa: E402
from babyrobot_marl.training.ppo.inputs import near_offsets  # noqa: E402
from babyrobot_marl.training.ppo.net import actor_probs  # noqa: E402
from babyrobot_marl.training.ppo.window import Atlas, Family, WindowForm  # noqa: E402

SMALL = PPOConfig(n_envs=32, n_steps=8, batch_size=1024, atlas_size=4, atlas_every=2, eval_every=0, trail=True)


def test_each_move_reads_what_the_trail_says_of_its_cell():
    # north: no move; east stood on at step 7; south at step 2 (left longest ago); west never
    value = trail_values(np.array([-1, 7, 2, 0]))
    assert trail_kinds(value)[0].tolist() == [[NO_MOVE, OLDEST + 1, OLDEST, NEVER]]
    assert trail_kinds(trail_values(np.zeros(4, dtype=int)))[0].tolist() == [[NEVER] * 4]
    # every order of the cells stood on among moves that lead somewhere: one number each, read back
    kinds = np.array([k for k in product(range(KINDS), repeat=4)
                      if sorted(v - OLDEST for v in k if v >= OLDEST) == list(range(sum(v >= OLDEST for v in k)))])
    times = np.where(kinds == NO_MOVE, -1, np.where(kinds == NEVER, 0, 10 * kinds))
    values = trail_values(times)
    assert (trail_kinds(values)[0] == kinds).all() and len(set(values.tolist())) == len(kinds)
    assert values.max() < KINDS**4 and TRAIL_VALUES == KINDS**4 * STILL
    # the steps stood still: a digit of their own, three or more alike
    assert [trail_kinds(trail_values(np.array([-1, 7, 2, 0]), s))[1][0] for s in range(6)] == [0, 1, 2, 3, 3, 3]
    # the kinds depend on the order alone: marking the robot's own cell again changes nothing
    assert trail_values(np.array([3, 0, 8, 5])) == trail_values(np.array([30, 0, 80, 50]))


def test_neighbours_are_the_moves_that_lead_to_another_cell():
    env = race_v0.parallel_env(level="maze:8..8", n_robots=1)
    atlas = Atlas([env.level], env.rules, WindowForm(2, (), False))
    nb = neighbours(atlas.table.target)
    level = atlas.level
    for c in range(level.n_cells):
        cell = (c % level.width, c // level.width)
        if cell in level.blocked:
            continue
        expected = {n[1] * level.width + n[0] for n, _ in level.neighbours(cell)}
        assert set(nb[c][nb[c] >= 0].tolist()) == expected


def _walk(atlas: Atlas, episodes: int, max_steps: int, seed: int, oldest: bool = True) -> np.ndarray:
    """One robot per env walking the vertex ant walk on its trail alone (never stood on first, else the
    neighbour left longest ago; ``oldest=False``: else the one left last): whose robot reached the exit."""
    batch = atlas.batch(episodes, 1, max_steps)
    batch.reset_drawn(np.arange(episodes), np.random.default_rng(seed))
    trails = Trails(atlas, episodes, 1)
    while not batch.over.all():
        kind = trail_kinds(trails.values(batch).reshape(-1))[0]  # (E, 4)
        order = np.where(kind == NO_MOVE, 99, np.where(kind == NEVER, 0, kind if oldest else 10 - kind))
        batch.step((order.argmin(axis=1) + 1)[:, None])
    return batch.rank[:, 0] > 0


def test_the_trail_alone_finds_every_exit_of_unseen_mazes():
    """What the trail shows is enough: a robot that reads nothing else and always steps to a cell never
    stood on, else the one left longest ago (the vertex ant walk), walks out of every maze, and the
    rule needs the order: a robot that steps back to the cell it left last instead stays in some mazes."""
    fam = Family(_source("maze:8..16"), 1, SMALL, 0, {})
    atlas = fam.atlas(16)
    reached = _walk(atlas, 64, fam.max_steps, 0)
    assert reached.all(), f"{(~reached).sum()} robots of 64 stayed in their mazes"
    assert not _walk(atlas, 64, fam.max_steps, 0, oldest=False).all()


def test_a_lone_robot_seeing_3x3_learns_from_its_trail_to_leave_larger_unseen_mazes():
    """The trail is an input a net learns from: one robot, a 3x3 window and its trail, a short run on mazes
    of side 5 to 8, then greedy on 200 unseen mazes of side 5 to 12 (up to 1.5 times the side it trained on)."""
    from babyrobot_marl.training.ppo.window import play_atlas

    cfg = PPOConfig(n_envs=256, n_steps=16, view_radius=1, trail=True, ent_coef=0.003, eval_every=0)
    result = train_ppo("maze:5..8", n_robots=1, timesteps=1_000_000, seed=0, config=cfg)
    fam = Family(_source("maze:5..12"), 1, result.config, 5, {})
    score = play_atlas(result.net, fam.atlas(200), 1, 200, fam.max_steps, np.random.default_rng(0))
    assert score["success_rate"] >= 0.95, score


def _source(spec: str):
    from babyrobot_marl.levels.sources import EVAL_MAZE_SEEDS, parse_level_family

    return parse_level_family(spec, EVAL_MAZE_SEEDS)


@pytest.fixture(scope="module")
def trained():
    return train_ppo("maze:8..10", n_robots=3, timesteps=20_000, seed=0, config=SMALL.replace(memory=True))


def test_each_bound_robot_reads_the_trail_the_trainer_keeps_over_whole_races(trained):
    """Rows built from the trainer's trails (``Trails`` beside the engine's cells) equal the rows each
    robot's own bound policy reads from race_v0's observations, over whole races, and so do the action
    probabilities (reading the same observation again changes nothing: the ranks keep their order)."""
    form = WindowForm(2, near_offsets(SMALL.near_radius), False, memory=True, trail=True)
    env = race_v0.parallel_env(level="maze:8..10", n_robots=3, observe="local", start="random", max_cycles=80)
    checked, values = 0, set()
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        robots = {a: trained.policy(deterministic=False, seed=seed).for_env(env) for a in env.possible_agents}
        atlas = Atlas([env.level], env.rules, form)
        trails = Trails(atlas, 1, 3)
        last = np.full((1, 3), 5)
        t = 0
        while env.agents:
            cells, racing = np.array(env._cells)[None, :], np.array(env._racing)[None, :]
            state = SimpleNamespace(cells=cells, racing=racing, pool=np.zeros(1, dtype=np.int64), t=np.array([t]))
            trail = trails.values(state)
            batch_rows = atlas.rows(atlas.keys(cells, racing, last, None, trail))
            actions = {}
            for a in env.agents:
                i = env.possible_agents.index(a)
                assert (robots[a].rows(obs[a])[0] == batch_rows[i]).all()
                p = actor_probs(trained.net, batch_rows[i : i + 1])[0]
                assert np.allclose(robots[a].action_probabilities(obs[a]), p)
                actions[a] = robots[a](obs[a])  # sampled: the robots wander, their trails grow
                last[0, i] = actions[a]
                values.add(int(trail[0, i]))
                checked += 1
            obs, *_ = env.step(actions)
            t += 1
    assert checked > 100 and len(values) > 5


def test_trail_is_for_level_families_saved_with_the_policy_and_fresh_per_binding(trained, tmp_path):
    with pytest.raises(ValueError, match="^trail: the trail input is read by a level family's policy"):
        train_ppo("maze-8x8", timesteps=10, config=SMALL)
    with pytest.raises(ValueError, match="^trail: must be True or False"):
        PPOConfig(trail=1)
    policy = load_policy(trained.save(str(tmp_path / "t.pt")))
    assert policy.form.trail and policy.form.n_in == trained.net.n_in
    env = race_v0.parallel_env(level="maze:8..8", n_robots=3, observe="local", start="random")
    obs, _ = env.reset(seed=0)
    with pytest.raises(ValueError, match="^obs: this policy reads its robot's trail on the env's level; bind it"):
        policy(obs["robot_0"])
    bound = policy.for_env(env)
    bound(obs["robot_0"])
    assert bound.trail.t == 1 and policy.for_env(env).trail.t == 0 and policy.trail.t == 0
    # reading the robot's probabilities marks nothing: acting does
    bound.action_probabilities(obs["robot_1"])
    assert bound.trail.t == 1


def test_train_with_a_trail_on_the_command_line_then_evaluate_race_and_play(tmp_path, capsys):
    from babyrobot_marl.cli import main
    from babyrobot_marl.training.policy import load_checkpoint

    path = str(tmp_path / "t.pt")
    assert main(["train", "--level", "maze:8..8", "--robots", "2", "--observe", "local", "--trail", "--recurrent",
                 "--hidden", "8", "--steps", "2000", "--n-envs", "16", "--save", path, "--episodes", "4",
                 "--no-progress"]) == 0
    assert "trail, a GRU of 8 units" in capsys.readouterr().out and load_checkpoint(path)["config"]["trail"] is True
    assert main(["evaluate", path, "--level", "maze:8..8", "--robots", "2", "--episodes", "3", "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert '"policy"' in out.splitlines()[-1] and "; each robot remembers its trail and a GRU of 8 units" in out
    assert main(["race", "--level", "maze:8..8", "--robots", "2", "--start", "random", "--policies", path]) == 0
    assert main(["play", "--level", "maze:8..8", "--policy", path, "--seed", "3", "--no-delay", "--max-steps", "20"]) == 0
    assert main(["train", "--level", "maze-8x8", "--steps", "10", "--trail"]) == 2
    assert "--trail: only with --observe local" in capsys.readouterr().err
