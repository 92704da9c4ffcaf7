"""Recurrent policies on the fast trainer: a GRU or a minGRU between the input layers and the heads, trained with
truncated backpropagation through time over rollout segments, one hidden state per robot in the trainer and per bound
policy."""

import numpy as np
import pytest

torch = pytest.importorskip("torch")

from babyrobot_marl import race_v0  # noqa: E402
from babyrobot_marl.cli import main  # noqa: E402
from babyrobot_marl.core.level import Level  # noqa: E402
from babyrobot_marl.training.policy import WindowPolicy, load_checkpoint, load_policy  # noqa: E402
from babyrobot_marl.training.ppo import PPOConfig, recurrent, train_ppo  # noqa: E402
from babyrobot_marl.training.ppo.inputs import near_offsets  # noqa: E402
from babyrobot_marl.training.ppo.recurrent import Recurrence, make_recurrent_net  # noqa: E402
from babyrobot_marl.training.ppo.sampler import distinct_below, distinct_rows  # noqa: E402
from babyrobot_marl.training.ppo.window import NO_ACTION, Atlas, Family, WindowForm, play_atlas  # noqa: E402

SMALL = PPOConfig(n_envs=32, n_steps=8, batch_size=768, atlas_size=4, atlas_every=2, eval_every=0, recurrent=True, hidden=8,
                  net_arch=(16,))


CELLS = ("gru", "mingru")


@pytest.fixture(scope="module", params=CELLS)
def trained(request):
    return train_ppo("maze:8..10", n_robots=3, timesteps=4_000, seed=0, config=SMALL.replace(cell=request.param))


def test_the_same_seed_gives_the_same_policy_and_the_same_evaluation(trained):
    config = SMALL.replace(cell=trained.net.cell)
    again = train_ppo("maze:8..10", n_robots=3, timesteps=4_000, seed=0, config=config)
    for (name, a), b in zip(trained.net.state_dict().items(), again.net.state_dict().values()):
        assert torch.equal(a, b), name
    other = train_ppo("maze:8..10", n_robots=3, timesteps=4_000, seed=1, config=config)
    cell = trained.net.gru.weight_hh if trained.net.cell == "gru" else trained.net.mingru.weight
    assert not torch.equal(cell, (other.net.gru.weight_hh if trained.net.cell == "gru" else other.net.mingru.weight))
    form = WindowForm(2, near_offsets(1), False)
    env = race_v0.parallel_env(level="maze:8..10", n_robots=3, start="random")
    env.reset(seed=0)
    atlas = Atlas([env.level], env.rules, form)
    for greedy in (True, False):
        runs = [play_atlas(net, atlas, 3, 8, 60, np.random.default_rng(5), greedy) for net in (trained.net, again.net)]
        assert runs[0] == runs[1]


def test_the_trainer_and_each_bound_robot_hold_the_same_rows_and_hidden_states_over_whole_races(trained):
    """Rows and hidden states built by the trainer's ``Recurrence`` from the batch engine's cells equal those each
    robot's own bound policy reads and keeps from race_v0's observations, and the greedy actions agree."""
    form = WindowForm(2, near_offsets(1), False)
    env = race_v0.parallel_env(level="maze:8..10", n_robots=3, observe="local", start="random", max_cycles=60)
    checked, moved = 0, 0
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        robots = {a: trained.policy().for_env(env) for a in env.possible_agents}  # one each, a fresh state
        atlas = Atlas([env.level], env.rules, form)
        rec = Recurrence(trained.net, 3, env.max_cycles + 1).start(atlas)
        while env.agents:
            cells, racing = np.array(env._cells)[None, :], np.array(env._racing)[None, :]
            keys = atlas.keys(cells, racing).reshape(-1)
            with torch.no_grad():
                rec.sample(keys, np.random.default_rng(0))
                greedy = rec.net.heads(rec.h)[0].argmax(1).numpy()
            rows = atlas.rows(keys)
            actions = {}
            for a in env.agents:
                i = env.possible_agents.index(a)
                assert (robots[a].rows(obs[a])[0] == rows[i]).all()
                actions[a] = robots[a](obs[a])
                # equal up to float rounding: a batch of robots and a single robot sum their products in another order
                assert torch.allclose(robots[a].hidden[0], rec.h[i], rtol=0, atol=1e-5) and actions[a] == greedy[i]
                checked += 1
            obs, *_ = env.step(actions)
            rec.ended(~np.array(env._racing))
            moved += float(rec.h.abs().sum()) > 0
    assert checked > 100 and moved > 0


@pytest.mark.parametrize("cell", CELLS)
def test_a_robots_state_is_zeroed_when_its_episode_ends_and_not_before(cell):
    """The trainer's state of a robot whose episode ended starts its next step from zero, as a new robot's;
    the others carry theirs on."""
    net = make_recurrent_net(6, (4,), 3, cell)
    inputs = _Flat(6)
    rec = Recurrence(net, 2, 4).start(inputs)
    rng = np.random.default_rng(0)
    with torch.no_grad():
        rec.sample(np.array([1, 2]), rng)
        rec.ended(np.array([False, False]))
        rec.sample(np.array([3, 4]), rng)
        rec.ended(np.array([True, False]))  # robot 0's episode ended at this step
        before = rec.h.clone()
        rec.sample(np.array([5, 5]), rng)
        fresh = net.step(net.gate_inputs(torch.tensor([[5]])), net.initial_state(1))[0]
        carried = net.step(net.gate_inputs(torch.tensor([[5]])), before[1:2])[0]
    assert torch.allclose(rec.h[0], fresh) and torch.allclose(rec.h[1], carried)
    assert not torch.allclose(rec.h[1], fresh)
    assert rec.keep_buf[:3].tolist() == [[True, True], [True, True], [False, True]]


@pytest.mark.parametrize("cell", CELLS)
def test_the_update_replays_each_segment_as_the_rollout_played_it(cell):
    """Truncated BPTT: replaying a rollout's segments from their first states with the rollout's resets gives
    the rollout's own log-probabilities (ratio 1 at the update's first step), across an episode's end."""
    net = make_recurrent_net(6, (4,), 3, cell)
    inputs = _Flat(6)
    T, n = 5, 4
    rec = Recurrence(net, n, T)
    rec.h = torch.randn(n, 3)  # a state carried over from the previous rollout
    rec.start(inputs)
    rng = np.random.default_rng(1)
    keys, actions = rng.integers(0, 6, (T, n)), np.zeros((T, n), dtype=np.int64)
    with torch.no_grad():
        for t in range(T):
            actions[t] = rec.sample(keys[t], rng)
            rec.ended(np.array([t == 1, False, t == 3, False]))
        rows, inv = distinct_rows(inputs, keys.reshape(-1))
        logits, values = rec.replay(rows, inv.view(T, n), torch.arange(n))
    logp = torch.log_softmax(logits, 1).view(T, n, 5).gather(2, torch.from_numpy(actions)[..., None])[..., 0]
    assert np.allclose(logp.numpy(), rec.logp_buf, atol=1e-6)
    assert np.allclose(values.view(T, n).numpy(), rec.value_buf, atol=1e-6)
    assert not rec.keep_buf[2, 0] and not rec.keep_buf[4, 2] and rec.keep_buf[:, 1].all()


class _Flat:
    """Inputs of one index per key (the key itself)."""

    def __init__(self, n: int):
        self.n_in = self.n_keys = n

    def rows(self, keys):
        return np.asarray(keys, dtype=np.int64).reshape(-1, 1)


def test_a_bound_policys_state_does_not_leak_into_the_next_episode(trained, tmp_path):
    env = race_v0.parallel_env(level="maze:8..10", n_robots=3, observe="local", start="random", max_cycles=60)
    obs, _ = env.reset(seed=4)
    fresh_actions = [trained.policy().for_env(env)(obs["robot_0"]) for _ in range(2)]
    bound = trained.policy().for_env(env)
    for _ in range(10):  # mid-episode: its state is no longer zero
        bound(obs["robot_0"])
    assert float(bound.hidden.abs().sum()) > 0
    saved = load_policy(trained.save(str(tmp_path / "r.pt")))
    assert isinstance(saved, WindowPolicy) and float(saved.hidden.abs().sum()) == 0
    nxt = bound.for_env(env)  # the next episode's robot: bound afresh
    assert float(nxt.hidden.abs().sum()) == 0 and nxt.last == NO_ACTION
    assert nxt(obs["robot_0"]) == fresh_actions[0] == saved.for_env(env)(obs["robot_0"])


def test_recurrent_policies_are_saved_loaded_and_checked(trained, tmp_path):
    path = trained.save(str(tmp_path / "r.pt"))
    data = load_checkpoint(path)
    assert data["config"]["recurrent"] is True and data["config"]["hidden"] == 8
    assert data["config"]["cell"] == trained.net.cell
    loaded = load_policy(path)
    assert loaded.net.cell == trained.net.cell
    for a, b in zip(loaded.net.state_dict().values(), trained.net.state_dict().values()):
        assert torch.equal(a, b)
    if trained.net.cell == "gru":  # a file saved before there was a choice of cell: a GRU
        del data["config"]["cell"]
        torch.save(data, tmp_path / "old.pt")
        assert load_policy(str(tmp_path / "old.pt")).net.cell == "gru"
    data["observation"] = {"observe": "global", "obs_encoding": "multidiscrete", "hint": False}
    torch.save(data, tmp_path / "bad.pt")
    with pytest.raises(ValueError, match="a recurrent policy reads local windows"):
        load_checkpoint(tmp_path / "bad.pt")
    with pytest.raises(ValueError, match="^recurrent: a recurrent net is read by a level family's policy"):
        train_ppo("maze-8x8", timesteps=10, config=SMALL)
    other = "mingru" if trained.net.cell == "gru" else "gru"
    names = {"gru": "a GRU", "mingru": "a minGRU"}
    with pytest.raises(ValueError, match=f"^init: .* and {names[trained.net.cell]} of 8 units; this run needs .* and "
                                         f"{names[other]} of 8 units"):
        train_ppo("maze:8..10", n_robots=3, timesteps=10, config=SMALL.replace(cell=other), init=trained.net)
    with pytest.raises(ValueError, match="^hidden: must be"):
        PPOConfig(hidden=0)
    with pytest.raises(ValueError, match="^recurrent: must be True or False"):
        PPOConfig(recurrent=1)


@pytest.mark.parametrize(("cell", "name"), [(None, "a GRU"), ("mingru", "a minGRU")])
def test_train_recurrent_on_the_command_line_then_evaluate_and_race(tmp_path, capsys, cell, name):
    path = str(tmp_path / "r.pt")
    chosen = [] if cell is None else ["--cell", cell]
    assert main(["train", "--level", "maze:8..8", "--robots", "2", "--observe", "local", "--recurrent", "--hidden", "8",
                 *chosen, "--steps", "2000", "--n-envs", "16", "--save", path, "--episodes", "4", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert f"{name} of 8 units" in out and load_checkpoint(path)["config"]["hidden"] == 8
    assert load_checkpoint(path)["config"]["cell"] == (cell or "gru")
    assert main(["evaluate", path, "--level", "maze:8..8", "--robots", "2", "--episodes", "3", "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert '"policy"' in out.splitlines()[-1] and f"{name} of 8 units" in out
    assert main(["race", "--level", "maze:8..8", "--robots", "2", "--start", "random", "--policies", path]) == 0
    refused = ((["--recurrent"], "--recurrent: only with --observe local"),
               (["--observe", "local", "--hidden", "8"], "--hidden: the recurrent cell's size, only with --recurrent"),
               (["--observe", "local", "--cell", "mingru"], "--cell: the recurrent cell's kind, only with --recurrent"))
    for args, message in refused:
        assert main(["train", "--level", "maze-8x8", "--steps", "10", *args]) == 2
        assert message in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["train", "--level", "maze-8x8", "--steps", "10", "--observe", "local", "--recurrent", "--cell", "lstm"])
    assert "--cell: invalid choice: 'lstm'" in capsys.readouterr().err


def test_the_step_from_precomputed_input_gates_is_torchs_gru_cell():
    net = make_recurrent_net(7, (5,), 4)
    rows, h = torch.tensor([[0, 3], [6, 7], [2, 2]]), torch.randn(3, 4)
    with torch.no_grad():
        assert torch.allclose(net.step(net.gate_inputs(rows), h), net.gru(net.encode(rows), h), atol=1e-6)


def test_the_mingru_step_is_its_formula():
    """``h' = (1 - z) h + z tanh(W_c x + b_c)``, ``z = sigmoid(W_z x + b_z)``: the gates read the input alone."""
    net = make_recurrent_net(7, (5,), 4, "mingru")
    rows, h = torch.tensor([[0, 3], [6, 7], [2, 2]]), torch.randn(3, 4)
    with torch.no_grad():
        net.mingru.bias.normal_()
        g = net.mingru(net.encode(rows))
        z, c = torch.sigmoid(g[:, :4]), torch.tanh(g[:, 4:])
        assert torch.allclose(net.step(net.gate_inputs(rows), h), (1 - z) * h + z * c, atol=1e-6)
        assert torch.allclose(net.gate_columns(rows).T, net.gate_inputs(rows), atol=1e-6)
    with pytest.raises(ValueError, match="^cell: the recurrent cell, one of 'gru', 'mingru', got 'lstm'"):
        PPOConfig(cell="lstm")


def _t_maze(side: int) -> Level:
    """A T: the arms along the top row, the exit at the end of one (``side`` -1: west, 1: east), a stem down the
    middle whose foot bends toward the exit's side (the cue). Seen through a window of radius 1, the junction
    and the stem's upper cells look the same in both mazes: only a robot that remembers the foot knows the way."""
    w, h = 7, 5
    free = {(x, 0) for x in range(w)} | {(w // 2, y) for y in range(1, h)} | {(w // 2 + side, h - 1)}
    return Level(w, h, blocked=[(x, y) for x in range(w) for y in range(h) if (x, y) not in free],
                 exits=[(0 if side < 0 else w - 1, 0)])


T_MAZES = (_t_maze(-1), _t_maze(1))
T_MAZE = PPOConfig(n_envs=32, n_steps=16, batch_size=512, atlas_size=8, atlas_every=4, eval_every=0, hidden=16,
                   net_arch=(32,), view_radius=1)


def _t_maze_success(policy: str, cell: str = "gru") -> float:
    """Greedy success over 400 episodes from random starts after 60,000 timesteps of training on the two T-mazes."""
    cfg = T_MAZE.replace(cell=cell, **{policy: True} if policy != "memoryless" else {})
    source = lambda rng: T_MAZES[int(rng.integers(2))]  # noqa: E731
    result = train_ppo(source, 1, 60_000, seed=1, config=cfg, env_kwargs={"max_cycles": 40})
    family = Family(source, 1, cfg, 0, {})
    return play_atlas(result.net, Atlas(list(T_MAZES), family.rules, family.form), 1, 400, 40,
                      np.random.default_rng(0))["success_rate"]


def test_a_recurrent_robot_learns_a_t_maze_that_only_memory_solves():
    """The cue at the stem's foot is out of view at the junction: a memoryless policy (or one that reads its last
    action) turns the same way in both mazes and cycles in the wrong arm; the recurrent one carries the cue."""
    recurrent, mingru = _t_maze_success("recurrent"), _t_maze_success("recurrent", "mingru")
    memoryless, last_action = _t_maze_success("memoryless"), _t_maze_success("memory")
    assert recurrent >= 0.85 and mingru >= 0.85, (recurrent, mingru)
    assert memoryless <= 0.7 and last_action <= 0.7, (memoryless, last_action)


@pytest.mark.parametrize("cell", CELLS)
def test_the_updates_gradient_through_time_is_autograds(cell):
    """The cell's backward pass through time, written out, gives autograd's gradient of the same loss over
    segments with resets and parked steps, for every parameter."""
    net = make_recurrent_net(6, (4,), 3, cell)
    T, n = 5, 4
    rec = Recurrence(net, n, T)
    rec.h = torch.randn(n, 3)
    rec.start(_Flat(6))
    rng = np.random.default_rng(2)
    keys, actions = rng.integers(0, 6, (T, n)), np.zeros((T, n), dtype=np.int64)
    with torch.no_grad():
        for t in range(T):
            actions[t] = rec.sample(keys[t], rng)
            rec.ended(np.array([t == 1, False, t == 3, False]))
    valid = np.ones((T, n), dtype=bool)
    valid[3:, 2] = False  # a robot parked after finishing
    adv, returns = rng.normal(size=(T, n)).astype(np.float32), rng.normal(size=(T, n)).astype(np.float32)
    cfg = PPOConfig(n_epochs=1, batch_size=T * n)
    rows, inv = distinct_rows(_Flat(6), keys.reshape(-1))
    seq = torch.arange(n)
    part = (torch.from_numpy(rec.logp_buf), torch.from_numpy(actions), torch.from_numpy(adv), torch.from_numpy(returns),
            torch.from_numpy(valid.astype(np.float32)))
    net.zero_grad()
    Recurrence.loss(*rec.replay(rows, inv.view(T, n), seq), *part, cfg).backward()
    expected = {name: p.grad.clone() for name, p in net.named_parameters()}
    params = list(net.parameters())
    for p in params:
        p.grad = None
    optim = torch.optim.SGD(params, lr=0.0)  # a step that changes nothing: only the gradients are compared
    rec.update(_Flat(6), keys, actions, adv, returns, valid, cfg, optim, params, torch.Generator())
    norm = float(torch.linalg.vector_norm(torch.stack([g.norm() for g in expected.values()])))
    clip = min(1.0, cfg.max_grad_norm / (norm + 1e-6))  # the update clips the gradient's norm
    for name, p in net.named_parameters():
        assert torch.allclose(p.grad, expected[name] * clip, atol=1e-6), name
        assert float(expected[name].abs().sum()) > 0, name  # every parameter is reached


def test_a_rollouts_input_gates_are_computed_once_per_input_and_equal_the_nets():
    """In a rollout the weights are fixed: each input's gate values are computed when a robot first meets it and
    read back after, equal to running the net on it."""
    from babyrobot_marl.training.ppo.sampler import Remembered

    net = make_recurrent_net(300, (4,), 3)
    seen = []

    def gates(rows):
        seen.extend(rows[:, 0].tolist())
        return net.gate_inputs(rows)

    inputs = _Flat(300)
    inputs.n_keys = 10**9  # too many keys for a full table: computed as met
    remembered = Remembered(inputs, gates)
    rng = np.random.default_rng(3)
    for _ in range(20):
        keys = rng.integers(0, 300, (2, 9))
        with torch.no_grad():
            direct = net.gate_inputs(torch.from_numpy(keys.reshape(-1, 1))).view(2, 9, -1)
        assert torch.allclose(torch.from_numpy(remembered(keys)), direct, atol=1e-6)
    assert sorted(seen) == sorted(set(seen))  # no key computed twice


def test_distinct_below_is_numpys_unique_with_its_inverse():
    for n, shape in ((50, (7, 9)), (3, (4, 4)), (1000, (2, 5))):
        keys = np.random.default_rng(n).integers(0, n, shape)
        want, want_inv = np.unique(keys, return_inverse=True)
        got, got_inv = distinct_below(keys, n)
        assert np.array_equal(got, want) and np.array_equal(got_inv, want_inv.reshape(shape))


def test_an_update_is_the_same_whether_its_one_hot_counts_are_built_once_or_per_minibatch(monkeypatch):
    """Several minibatches of windows (rows of many indices): the counts built once per update, in memory kept from
    one update to the next, train the same weights as counts built per minibatch."""
    config = SMALL.replace(cell="mingru", batch_size=128)  # 8 steps of 32 envs of 3 robots: 6 minibatches
    kept = train_ppo("maze:8..10", n_robots=3, timesteps=4_000, seed=0, config=config).net.state_dict()
    monkeypatch.setattr(recurrent, "DENSE_ROOM", 0)
    each = train_ppo("maze:8..10", n_robots=3, timesteps=4_000, seed=0, config=config).net.state_dict()
    assert all(torch.equal(kept[name], each[name]) for name in kept)
