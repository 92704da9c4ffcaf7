"""A crowd that imitates PIBT (``PPOConfig(imitate="pibt")``, ``train --imitate pibt``): what the robots near each
robot intend, read alike from the batch engine and from race_v0; DAgger learns a crowd far better than an
untrained one; its settings saved and read back; the CLI refuses what it cannot do by flag, before training."""

import json
from concurrent.futures import Future
from dataclasses import replace

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from babyrobot_marl import race_v0  # noqa: E402
from babyrobot_marl.core.actions import Action  # noqa: E402
from babyrobot_marl.core.level import Level  # noqa: E402
from babyrobot_marl.planning import PIBT  # noqa: E402
from babyrobot_marl.training.policy import WindowPolicy, load_checkpoint, load_policy  # noqa: E402
from babyrobot_marl.training.ppo import PPOConfig, train_ppo  # noqa: E402
from babyrobot_marl.training.ppo.form import NO_ACTION  # noqa: E402
from babyrobot_marl.training.ppo.inputs import near_offsets  # noqa: E402
from babyrobot_marl.training.ppo.intents import Ranks, env_intents, env_ranks  # noqa: E402
from babyrobot_marl.training.ppo.net import actor_probs, make_net  # noqa: E402
from babyrobot_marl.training.ppo.sampler import sample_actions  # noqa: E402
from babyrobot_marl.training.ppo.turns import decide_in_turns, turn_rows, waves  # noqa: E402
from babyrobot_marl.training.ppo.window import Atlas, Family, WindowForm  # noqa: E402

STAY = {"goals": "own", "collisions": "soft", "finished": "stay"}
FORM = WindowForm(2, near_offsets(2), True, goals="own", intents=True, ranks=True, turns=True)
GRID = "\n".join([".....#....", ".##..#.##.", ".#.......#", ".#.##.#...", "......#.#.", "##.#....#.",
                  "...#.##...", ".#...#..#.", ".#.#...##.", "...#.#...."])


def _units(row: np.ndarray, form: WindowForm, offset: tuple[int, int]) -> set[int]:
    """The intent units set in ``row`` for the near cell at ``offset`` (0-3: moves north..west, 4: on its target,
    5: goes first)."""
    k, u = form.near.index(offset), form.intent_units
    part = row[k * u : (k + 1) * u]
    return {int(v - form.intents_first - k * u) for v in part if v != form.n_in}


def test_a_robot_reads_where_its_neighbours_go_and_whether_they_are_home():
    env = race_v0.parallel_env(level=Level.from_grid("\n".join(["......"] * 3)), n_robots=3, observe="local", hint=True,
                               start="random", **STAY)
    env.reset(seed=0, options={"starts": [(1, 1), (2, 0), (1, 2)], "goals": [(5, 1), (2, 1), (1, 0)]})
    env.step({"robot_0": Action.STAY, "robot_1": Action.SOUTH, "robot_2": Action.STAY})  # robot 1 arrives
    rows = env_intents(env, FORM)  # robots 0 and 2 have stood off their targets two steps, robot 1 none: 2 goes first
    assert rows.shape == (3, len(FORM.near) * 6)
    assert _units(rows[0], FORM, (1, 0)) == {4}  # robot 1, east of robot 0, stands on its target
    assert _units(rows[0], FORM, (0, 1)) == {Action.NORTH - 1, 5}  # robot 2, south of it, heads north, goes first
    assert _units(rows[1], FORM, (-1, 0)) == {Action.EAST - 1, 5}  # robot 0 heads east, into robot 1's cell
    assert _units(rows[1], FORM, (-1, 1)) == {Action.NORTH - 1, 5}
    assert _units(rows[2], FORM, (0, -1)) == {Action.EAST - 1} and _units(rows[2], FORM, (1, -1)) == {4}
    assert (env_intents(env, FORM) == rows).all()  # read again at the same step: the same ranks
    seen = [(i, k) for i in range(3) for k in FORM.near if _units(rows[i], FORM, k)]
    assert len(seen) == 6  # each robot sees the other two, nothing else
    env.step({"robot_0": Action.STAY, "robot_1": Action.NORTH, "robot_2": Action.STAY})  # robot 1 steps off again
    rows = env_intents(env, FORM)  # one step off its target against robot 0's three: robot 0 still goes first
    assert _units(rows[0], FORM, (1, -1)) == {Action.SOUTH - 1} and _units(rows[1], FORM, (-1, 1)) == {Action.EAST - 1, 5}


@pytest.mark.parametrize("level", ["gridmaze:9..11", Level.from_grid(GRID)])
def test_the_batch_engine_and_a_bound_policy_read_the_same_rows(level):
    """The judge's rows (the batch engine's keys and ``Atlas.intents``) equal a bound ``WindowPolicy``'s, robot by
    robot, over random races; the intents change as robots move and arrive."""
    env = race_v0.parallel_env(level=level, n_robots=8, observe="local", hint=True, start="random", max_cycles=40, **STAY)
    policy = WindowPolicy(make_net(FORM.n_in, (16,)), FORM, 8)
    rng = np.random.default_rng(0)
    checked, kinds = 0, set()
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        bound = policy.for_env(env)
        atlas = Atlas([env.level], env.rules, FORM, stay=True)
        w = env.level.width
        ranks = Ranks(8)  # the judge's, beside the batch engine
        while env.agents:
            cells, racing = np.array(env._cells)[None, :], np.array(env._racing)[None, :]
            goals = np.array([[env.goals[a][1] * w + env.goals[a][0] for a in env.possible_agents]])
            order = ranks.values(cells, goals, np.array([env.elapsed_steps]))
            intents = atlas.intents(atlas.near_robots(cells, racing), cells, goals, order)
            rows = np.concatenate([atlas.rows(atlas.keys(cells, racing, None, goals)), intents], axis=1)
            for a in env.agents:
                i = env.possible_agents.index(a)
                assert (bound.rows(obs[a])[0] == rows[i]).all()
                checked += 1
            kinds.update((intents[intents < FORM.n_in] - FORM.intents_first) % FORM.intent_units)
            obs, *_ = env.step({a: int(rng.integers(5)) for a in env.agents})
    assert checked > 500 and kinds == {0, 1, 2, 3, 4, 5}


def _judge_rows(env, atlas, ranks, last):
    """The batch engine's view of a race env's step: base rows, near robots, priorities, racing."""
    w = env.level.width
    cells, racing = np.array(env._cells)[None, :], np.array(env._racing)[None, :]
    goals = np.array([[env.goals[a][1] * w + env.goals[a][0] for a in env.possible_agents]])
    order = ranks.values(cells, goals, np.array([env.elapsed_steps]))
    there = atlas.near_robots(cells, racing)
    base = np.concatenate([atlas.rows(atlas.keys(cells, racing, last, goals)), atlas.intents(there, cells, goals, order)],
                          axis=1)
    return base, there, order, racing


def _hashed(rows: np.ndarray) -> np.ndarray:
    """Probabilities that change with every index of a row: one action, a hash of the row."""
    p = np.zeros((len(rows), 5))
    p[np.arange(len(rows)), (rows * np.arange(1, rows.shape[1] + 1) * 7919).sum(axis=1) % 5] = 1.0
    return p


def test_robots_in_turns_choose_as_one_at_a_time_in_priority_order():
    """Turn by turn (``waves``, one net pass per turn) the crowd chooses what it would choose robot by robot from
    the highest priority down, each reading the choices of the near robots before it; a crowd takes several turns."""
    env = race_v0.parallel_env(level="gridmaze:11..13", n_robots=16, observe="local", hint=True, start="random",
                               max_cycles=30, **STAY)
    rng = np.random.default_rng(0)
    most = 0
    for seed in range(3):
        env.reset(seed=seed)
        atlas = Atlas([env.level], env.rules, FORM, stay=True)
        ranks = Ranks(16)
        while env.agents:
            base, there, order, racing = _judge_rows(env, atlas, ranks, None)
            pick = lambda p: p.argmax(axis=1)  # noqa: E731
            chosen, _ = decide_in_turns(base, there, order, racing, _hashed, pick, FORM.turns_first, FORM.n_in)
            one = np.full((1, 16), -1)
            for i in np.argsort(-order[0]):
                row = np.concatenate([base[i], turn_rows(there, order, one, FORM.turns_first, FORM.n_in)[i]])
                one[0, i] = pick(_hashed(row[None]))[0]
            assert np.array_equal(chosen, one)
            most = max(most, int(waves(there, order).max()))
            env.step({a: int(rng.integers(5)) for a in env.agents})
    assert most >= 2  # some robot waited for a robot that waited for another


@pytest.mark.parametrize("level", ["gridmaze:9..11", Level.from_grid(GRID)])
def test_a_bound_crowd_decides_in_turns_as_the_trainers_judge_does(level):
    """Bound policies, one per robot, answer from one plan per step (``env_turn``) that equals the batch engine's
    (sampled from the same seed): the same rows, last actions, priorities and choices in the same turns."""
    form = replace(FORM, memory=True)
    env = race_v0.parallel_env(level=level, n_robots=8, observe="local", hint=True, start="random", max_cycles=30, **STAY)
    net = make_net(form.n_in, (32,))
    policy = WindowPolicy(net, form, 8, deterministic=False, seed=5)
    judge_rng, steps = np.random.default_rng(5), 0

    def probs(rows):
        return actor_probs(net, rows)

    for seed in range(2):
        obs, _ = env.reset(seed=seed)
        robots = [policy.for_env(env) for _ in env.possible_agents]
        atlas = Atlas([env.level], env.rules, form, stay=True)
        ranks, last = Ranks(8), np.full((1, 8), NO_ACTION)
        while env.agents:
            base, there, order, racing = _judge_rows(env, atlas, ranks, last)
            want, _ = decide_in_turns(base, there, order, racing, probs, lambda p: sample_actions(p, judge_rng),
                                      form.turns_first, form.n_in)
            acts = {a: robots[i](obs[a]) for i, a in enumerate(env.possible_agents) if a in env.agents}
            assert [acts[a] for a in env.possible_agents] == want[0].tolist()
            last, steps = want, steps + 1
            obs, *_ = env.step(acts)
    assert steps >= 40


def test_a_bound_crowds_plan_is_made_again_after_a_reset_to_the_same_cells_with_other_targets():
    """``env_turn`` keys its plan on the env's state: the same step 0 and cells with other targets (a reset with
    ``options``) is another state, planned afresh, as a new env would plan it."""
    from babyrobot_marl.training.ppo import turns

    net = make_net(FORM.n_in, (32,))
    starts = [(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (3, 1)]

    def crowd():
        return race_v0.parallel_env(level=Level.from_grid(GRID), n_robots=6, observe="local", hint=True, start="random",
                                    max_cycles=12, **STAY)

    env, plans = crowd(), []
    for goals in ([(9, 9), (0, 9), (9, 0), (0, 2), (6, 2), (4, 5)], [(2, 2), (7, 0), (0, 7), (7, 9), (4, 4), (2, 7)]):
        fresh = crowd()
        for e in (env, fresh):
            e.reset(seed=0, options={"starts": starts, "goals": goals})
        plan, want = (turns.env_turn(e, FORM, lambda o: np.asarray(o).reshape(-1), lambda r: actor_probs(net, r),
                                     lambda p: p.argmax(1)) for e in (env, fresh))
        assert np.array_equal(plan.probs, want.probs) and np.array_equal(plan.actions, want.actions)
        plans.append(plan)
    assert plans[1] is not plans[0] and not np.array_equal(plans[1].probs, plans[0].probs)


def test_a_race_env_shows_its_observations_as_its_last_step_returned():
    env = race_v0.parallel_env(level="gridmaze:9..11", n_robots=6, observe="local", hint=True, start="random",
                               max_cycles=20, **STAY)
    obs, _ = env.reset(seed=1)
    rng = np.random.default_rng(1)
    while env.agents:
        now = env.unwrapped.observations()
        assert now.keys() == obs.keys() and all(np.array_equal(now[a], obs[a]) for a in obs)
        obs, *_ = env.step({a: int(rng.integers(5)) for a in env.agents})


def test_the_judges_ranks_grow_with_the_batch_engines_step_count():
    """The judge reads ranks at the batch engine's own step counter, which the engine counts up in place: robots
    that stand still off their targets go up one a step."""
    env = race_v0.parallel_env(level=Level.from_grid(GRID), n_robots=4, observe="local", hint=True, start="random", **STAY)
    atlas = Atlas([env.level], env.rules, FORM, stay=True)
    batch = atlas.batch(3, 4, 10)
    batch.reset_drawn(np.arange(3), np.random.default_rng(0))
    ranks = Ranks(4)
    for step in range(5):
        values = ranks.values(batch.cells, batch.goals, batch.t)
        off = batch.cells != batch.goals
        assert off.all() and np.array_equal(np.floor(values), np.where(off, step + 1, 0))
        batch.step(np.zeros((3, 4), dtype=np.int64))  # everyone stays


def test_a_step_computes_the_crowds_intents_once_for_all_its_robots(monkeypatch):
    """``robot_intents`` answers every robot's call of a step from one ``env_intents`` of the crowd, the rows a twin env
    (the same races, its own priorities) computes for each robot; a new step (one where every robot stays too) and a
    reset to the same cells with other targets compute them again."""
    from babyrobot_marl.training.ppo import intents

    uncached, calls = intents.env_intents, []
    monkeypatch.setattr(intents, "env_intents", lambda env, form: calls.append(env.elapsed_steps) or uncached(env, form))
    env, twin = (race_v0.parallel_env(level=Level.from_grid(GRID), n_robots=6, observe="local", hint=True, start="random",
                                      max_cycles=12, **STAY) for _ in range(2))
    rng = np.random.default_rng(0)

    def every_robot() -> np.ndarray:
        crowd = uncached(twin, FORM)
        for a in env.agents:
            i = env.possible_agents.index(a)
            row = intents.robot_intents(env, FORM, env.robot_cells[i])
            assert row.shape == (1, crowd.shape[1]) and np.array_equal(row, crowd[i : i + 1])
        return crowd

    steps = 0
    for seed in range(2):
        for e in (env, twin):
            e.reset(seed=seed)
        while env.agents:
            every_robot()
            steps += 1
            assert len(calls) == steps  # once per step, not once per robot
            stay = steps % 3 == 0  # nobody moves: the step, and with it the priorities, still changes
            actions = {a: Action.STAY if stay else int(rng.integers(5)) for a in env.agents}
            for e in (env, twin):
                e.step(actions)
    assert steps == 24
    starts = [(0, 0), (1, 0), (2, 0), (3, 0), (4, 0), (3, 1)]  # near each other
    for goals in ([(9, 9), (0, 9), (9, 0), (0, 2), (6, 2), (4, 5)], [(2, 2), (7, 0), (0, 7), (7, 9), (4, 4), (2, 7)]):
        for e in (env, twin):
            e.reset(seed=0, options={"starts": starts, "goals": goals})
        crowd = every_robot()  # the same step 0 and cells, other targets: computed again
        assert (crowd != FORM.n_in).any() and len(calls) == steps + 1
        steps += 1
    uncached(env, FORM)  # the priorities read by another since (env_turn, say): computed again, the same rows
    assert np.array_equal(intents.robot_intents(env, FORM, starts[0]), crowd[:1]) and len(calls) == steps + 1


def test_the_robots_keep_pibts_priorities():
    """The ranks a race's robots keep (``env_ranks``) are PIBT's own priorities over whole episodes (PIBT driving,
    its ties those of the ranks), so the rows an imitation crowd learns from tell who PIBT lets go first."""
    env = race_v0.parallel_env(level="gridmaze:9..11", n_robots=8, observe="local", hint=True, start="random",
                               max_cycles=40, **STAY)
    steps = arrived = 0
    for seed in range(3):
        env.reset(seed=seed)
        planner = PIBT(env.level, [env.goals[a] for a in env.possible_agents], seed=seed)
        planner.priority = Ranks(8).ties.tolist()
        while env.agents:
            env_intents(env, FORM)
            actions = planner.actions(env.robot_cells)
            ours = env_ranks(env.unwrapped)
            assert np.allclose(ours.elapsed[0] + ours.ties, planner.priority)
            arrived += int(sum(p < 1 for p in planner.priority))
            steps += 1
            env.step(dict(zip(env.possible_agents, actions)))
    assert steps > 60 and arrived > 0  # robots reached their targets: their priorities fell below one


@pytest.mark.train
def test_dagger_on_pibt_learns_a_crowd_that_brings_its_robots_home(tmp_path):
    """A few rounds of DAgger on small grid mazes: on unseen mazes of the family the learnt crowd (sampled) brings far
    more robots to their targets than the same net untrained; the saved policy records it and reads the intents."""
    config = PPOConfig(imitate="pibt", hint=True, memory=True, near_radius=2, net_arch=(64, 64), learning_rate=1e-3,
                       batch_size=1024, eval_every=0)
    kwargs = {**STAY, "max_cycles": 48}
    result = train_ppo("gridmaze:7..9", n_robots=6, timesteps=60_000, seed=0, config=config, env_kwargs=kwargs)
    from babyrobot_marl.levels.sources import EVAL_MAZE_SEEDS, parse_level_family

    judge = Family(parse_level_family("gridmaze:7..9", EVAL_MAZE_SEEDS), 6, config, 1, kwargs)
    untrained = make_net(judge.form.n_in, config.net_arch)
    learnt = judge.play(result.net, 64, 16, np.random.default_rng(2), deterministic=False)
    judge.rng = np.random.default_rng([1, 2])
    before = judge.play(untrained, 64, 16, np.random.default_rng(2), deterministic=False)
    assert learnt["success_rate"] >= 0.8 and learnt["success_rate"] >= before["success_rate"] + 0.4, (learnt, before)
    path = result.save(str(tmp_path / "crowd.pt"))
    assert load_checkpoint(path)["config"]["imitate"] == "pibt"
    policy = load_policy(path)
    assert policy.form.intents and policy.form.ranks and policy.form.n_in == FORM.n_in + 5  # ... and memory


@pytest.mark.parametrize("argv, first", [
    (["--goals", "exit"], "--imitate: "),
    (["--collisions", "block"], "--imitate: "),
    (["--finished", "remove"], "--imitate: "),
    (["--robots", "1"], "--imitate: "),
    (["--trail"], "--imitate: "),
    (["--ent-coef", "0.1"], "--imitate: "),
    (["--observe", "global", "--level", "maze-8x8"], "--hint: "),
])
def test_train_refuses_what_imitation_cannot_do_by_flag(argv, first, capsys, monkeypatch):
    from babyrobot_marl.training.ppo import loop
    from tests.cli_run import run

    monkeypatch.setattr(loop, "train_ppo", lambda *a, **k: pytest.fail("training started"))
    base = ["train", "--level", "gridmaze:9..11", "--robots", "4", "--observe", "local", "--hint", "--goals", "own",
            "--collisions", "soft", "--finished", "stay", "--imitate", "pibt", "--steps", "1000"]
    assert run(base + argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"babyrobot-marl: error: {first}") and err.count("\n") == 1, err


def test_a_short_imitation_run_saves_and_evaluates_and_races(tmp_path, capsys):
    from tests.cli_run import run

    path = tmp_path / "crowd.pt"
    argv = ["train", "--level", "gridmaze:9..11", "--robots", "4", "--observe", "local", "--hint", "--goals", "own",
            "--collisions", "soft", "--finished", "stay", "--imitate", "pibt", "--max-cycles", "32", "--steps", "1000",
            "--episodes", "8", "--save", str(path), "--no-progress"]
    assert run(argv) == 0
    out = capsys.readouterr().out
    assert "imitation of PIBT" in out and "the near robots' intents, in turns" in out and "sampled:" in out
    assert json.loads(out.splitlines()[-1])["timesteps"] >= 1000
    assert run(["evaluate", str(path), "--level", "gridmaze:7..9", "--robots", "4", "--episodes", "4"]) == 0
    figures = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert 0 <= figures["policy"]["success_rate"] <= 1
    assert run(["race", "--level", "gridmaze:9..11", "--robots", "4", "--goals", "own", "--collisions", "soft",
                "--start", "random", "--policies", str(path), "--max-cycles", "16"]) == 0


@pytest.mark.parametrize("settings, kwargs, first", [
    ({"imitate": "lacam"}, None, "imitate: must be None or one of 'pibt'"),
    ({"imitate": "pibt", "trail": True}, None, "imitate: "),
    ({"imitate": "pibt"}, {"goals": "own", "collisions": "soft"}, "imitate: PIBT's robots stay"),
    ({"imitate": "pibt"}, {"goals": "own", "finished": "stay"}, "imitate: PIBT's moves are learnt under POGEMA's rule"),
    ({"imitate": "pibt"}, {}, "imitate: PIBT plans for a crowd of own goals"),
])
def test_the_api_refuses_what_imitation_cannot_do_in_one_line(settings, kwargs, first):
    with pytest.raises(ValueError) as err:
        level = "maze:8..10" if kwargs == {} else "gridmaze:9..11"  # a race to the exits needs exits
        train_ppo(level, n_robots=4, timesteps=100, config=PPOConfig(**settings), env_kwargs=kwargs)
    assert str(err.value).startswith(first) and "\n" not in str(err.value)


class _Deferred(Future):
    """A round's collection run only when its result is asked for: after the learning it overlaps."""

    def __init__(self, fn, args):
        super().__init__()
        self.fn, self.args = fn, args

    def result(self, timeout=None):
        if not self.done():
            self.set_result(self.fn(*self.args))
        return super().result()


class _Executor:
    """A stand-in for the trainer's collection thread: ``eager`` runs each round at once (before the learning
    it overlaps), otherwise after it."""

    def __init__(self, eager: bool):
        self.eager = eager

    def __call__(self, workers):
        return self

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def submit(self, fn, *args):
        future = _Deferred(fn, args)
        if self.eager:
            future.result()
        return future


def test_the_same_seed_imitates_into_the_same_net_whichever_thread_runs_first(monkeypatch):
    """The next round's episodes play on a thread of their own while the net learns; a copy of the net drives
    them, so the weights do not hang on which thread runs first (rounds collected before, during or after the
    learning they overlap); another seed gives other weights."""
    from babyrobot_marl.training.ppo import imitation

    config = PPOConfig(imitate="pibt", hint=True, memory=True, near_radius=2, net_arch=(32,), learning_rate=1e-3,
                       batch_size=512, eval_every=0)
    kwargs = {**STAY, "max_cycles": 32}

    def weights(seed: int) -> list:
        net = train_ppo("gridmaze:7..9", n_robots=4, timesteps=5000, seed=seed, config=config, env_kwargs=kwargs).net
        return [v.numpy().copy() for v in net.state_dict().values()]

    first, again, other = weights(0), weights(0), weights(1)
    for eager in (True, False):
        monkeypatch.setattr(imitation, "ThreadPoolExecutor", _Executor(eager))
        assert all((a == b).all() for a, b in zip(first, weights(0))), eager
    assert all((a == b).all() for a, b in zip(first, again))
    assert not all((a == b).all() for a, b in zip(first, other))


def test_an_input_too_wide_for_a_64_bit_key_is_refused_by_name():
    """Robots within 4 steps (40 bits), own targets with the hint in a 9x9 window and the last action: more than
    64 bits of key, which would wrap around silently; refused before training, naming near_radius."""
    config = PPOConfig(view_radius=4, near_radius=4, hint=True, memory=True, eval_every=0)
    with pytest.raises(ValueError, match=r"^near_radius: 4 with a window of view_radius 4"):
        train_ppo("gridmaze:9..11", n_robots=4, timesteps=100, config=config, env_kwargs=STAY)
    train_ppo("gridmaze:9..11", n_robots=4, timesteps=100, config=config.replace(near_radius=3, n_envs=8, n_steps=4),
              env_kwargs=STAY)  # 3 fits


def test_the_labelled_steps_keep_the_newest_within_their_memory():
    """Labelled steps grow until their memory is full, then each new row replaces the oldest; each row keeps its
    label, and ``fresh`` counts the rows added since it was last asked."""
    from babyrobot_marl.training.ppo.imitation import Labelled

    seen = Labelled(np.int16, memory=10 * 3 * 2)  # ten rows of three int16 indices
    added = []
    for step in range(9):
        seen.add(np.full((3, 3), step, np.int16), np.full(3, step, np.int8))
        added += [step] * 3
        assert sorted(seen.labels[: seen.n].tolist()) == sorted(added[-10:])
        assert (seen.rows[: seen.n] == seen.labels[: seen.n, None]).all()
    assert (seen.n, seen.fresh(), seen.fresh()) == (10, 27, 0)
