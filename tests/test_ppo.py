"""The fast PPO trainer (the training/ppo/ package): it learns, its gradient is PPO's, its input is the env's
observation as a one-hot, it is deterministic, and a saved policy acts as the trained one."""

from __future__ import annotations

import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="needs the train extra")  # CI installs it (test extra)

from babyrobot_marl import BabyRobotEnv, levels, race_v0  # noqa: E402
from babyrobot_marl.training.evaluate import race_rates  # noqa: E402
from babyrobot_marl.training.policy import TrainedPolicy, load_policy, make_policy  # noqa: E402
from babyrobot_marl.training.ppo import (  # noqa: E402
    Inputs,
    PPOConfig,
    Samples,
    make_batch,
    make_inputs,
    make_net,
    near_offsets,
    ppo_gradients,
    torch_threads,
    train_ppo,
)
from babyrobot_marl.training.single import evaluate_single, optimal_return  # noqa: E402

SMALL = PPOConfig(n_envs=32, n_steps=16, batch_size=256, n_epochs=4, learning_rate=3e-3, eval_every=0)


@pytest.mark.parametrize(("level", "timesteps"), [("default", 8192), ("walls", 40960)])
def test_a_short_seeded_run_learns_the_optimum_from_the_start(level, timesteps):
    result = train_ppo(level, 1, timesteps, seed=0, config=SMALL)
    env = BabyRobotEnv(level=level)
    assert evaluate_single(result.policy(), env, episodes=1).mean == optimal_return(env)


def test_the_race_policy_beats_random_robots_after_a_short_run():
    lv = levels.get("race-2")
    result = train_ppo(lv, 2, 60_000, seed=0, config=SMALL)
    trained = race_rates(result.policy(), lv, 2, "random", races=100, seed=1).win_rate
    inputs = make_inputs(lv, 2, SMALL.near_radius)
    untrained = race_rates(TrainedPolicy(make_net(inputs.n_in), inputs, 2), lv, 2, "random", 100, 1).win_rate
    assert trained >= 0.9 > untrained


def _reference_loss(net, idx, act, old, adv, ret, cfg):
    """SB3's PPO loss through autograd, written independently of ``ppo_gradients``."""
    logits, values = net(idx)
    logp_all = torch.log_softmax(logits, 1)
    logp = logp_all.gather(1, act[:, None])[:, 0]
    entropy = -(logp_all.exp() * logp_all).sum(1)
    a = (adv - adv.mean()) / (adv.std() + 1e-8)
    ratio = torch.exp(logp - old)
    pg = -torch.min(a * ratio, a * torch.clamp(ratio, 1 - cfg.clip_range, 1 + cfg.clip_range)).mean()
    return pg - cfg.ent_coef * entropy.mean() + cfg.vf_coef * torch.nn.functional.mse_loss(values, ret)


@pytest.mark.parametrize(("k", "n_in"), [(1, 25), (3, 50)])
def test_the_hand_written_gradient_is_autograds_gradient_of_ppos_loss(k, n_in):
    torch.manual_seed(0)
    net, cfg, b = make_net(n_in, (16, 8)), PPOConfig(), 200
    idx = torch.randint(0, n_in + (k > 1), (b, k))  # rows repeat; the race's include the padding row
    if k == 1:
        cells, inv = torch.unique(idx[:, 0], return_inverse=True)
        rows = cells[:, None]
    else:
        rows, inv = torch.unique(idx, dim=0, return_inverse=True)
    act = torch.randint(0, 5, (b,))
    old_rows = torch.log_softmax(torch.randn(rows.shape[0], 5) * 2.0, 1)  # the rollout's policy: ratios both sides of the clip
    old = old_rows[inv, act]  # a sample's old log-probability is its row's and action's
    adv, ret = torch.randn(b), torch.randn(b)
    _reference_loss(net, idx, act, old, adv, ret, cfg).backward()
    expected = [p.grad.clone() for p in net.parameters()]
    ratio = torch.exp(torch.log_softmax(net.actor(rows), 1) - old_rows)[inv, act]
    assert ((ratio < 0.8) & (adv > 0)).any() and ((ratio > 1.2) & (adv < 0)).any() and ((ratio > 1.2) & (adv > 0)).any()
    ppo_gradients(net, rows, old_rows, Samples.of(inv, act, adv, ret), cfg)
    for (name, p), want in zip(net.named_parameters(), expected):
        if name.endswith("first"):  # the padding row (a finished robot) is no input: it stays zero
            assert not p.grad[n_in].any()
            p, want = p.grad[:n_in], want[:n_in]
        else:
            p = p.grad
        assert torch.allclose(p, want, atol=1e-6, rtol=1e-4), name
    assert max(float(g.abs().max()) for g in expected) > 1e-3  # not a vacuous comparison


def _input_from_observation(obs, w, h, n_robots, radius):
    """The input the net means, built by hand from a single env's MultiDiscrete observation: the
    one-hot of the robot's cell, then for each offset within ``radius`` steps (Manhattan, row by
    row) a 1 when a racing robot stands there."""
    x, y = int(obs[0]), int(obs[1])
    near = [] if n_robots == 1 else [(dx, dy) for dy in range(-radius, radius + 1) for dx in range(-radius, radius + 1)
                                     if 0 < abs(dx) + abs(dy) <= radius]
    vec = np.zeros(w * h + len(near), dtype=np.float32)
    vec[y * w + x] = 1
    others = {(int(ox), int(oy)) for ox, oy, finished in np.asarray(obs[2:]).reshape(-1, 3) if not finished}
    for b, (dx, dy) in enumerate(near):
        vec[w * h + b] = (x + dx, y + dy) in others
    return vec


def test_near_offsets_are_the_cells_within_the_radius():
    assert near_offsets(0) == ()
    assert set(near_offsets(1)) == {(1, 0), (-1, 0), (0, 1), (0, -1)}
    assert len(near_offsets(2)) == 12 and all(0 < abs(dx) + abs(dy) <= 2 for dx, dy in near_offsets(2))


@pytest.mark.parametrize(("n_robots", "radius"), [(1, 2), (3, 1), (4, 2), (4, 3)])
def test_the_batch_encoding_is_the_input_built_from_the_single_envs_observation(n_robots, radius):
    level = levels.get("race-4")
    w, h, e = level.width, level.height, 4
    if n_robots == 1:
        envs = [BabyRobotEnv(level=level, start="random") for _ in range(e)]
    else:
        envs = [race_v0.parallel_env(level=level, n_robots=n_robots, start="random", finished="freeze") for _ in range(e)]
    inputs = make_inputs(level, n_robots, radius)
    batch = make_batch(level, n_robots, e, "random", seed=5)
    obs = [env.reset(seed=5 + i)[0] for i, env in enumerate(envs)]
    rng = np.random.default_rng(0)
    checked = near = 0
    for _ in range(60):
        keys = inputs.keys(batch.cells, batch.racing)
        for i, env in enumerate(envs):
            agents = ["single"] if n_robots == 1 else env.possible_agents
            for r, agent in enumerate(agents):
                o = obs[i] if n_robots == 1 else obs[i][agent]
                assert keys[i, r] == inputs.key_of_observation(o)
                want = _input_from_observation(o, w, h, n_robots, radius)
                assert np.array_equal(inputs.one_hot(keys[i, r]), want)
                checked += 1
                near += bool(want[w * h:].any())
        actions = rng.integers(0, 5, size=(e, n_robots))
        _, _, _, _, over = batch.step(actions)
        if over.any():
            break
        for i, env in enumerate(envs):
            if n_robots == 1:
                obs[i] = env.step(int(actions[i, 0]))[0]
            else:
                live = {a: int(actions[i, k]) for k, a in enumerate(env.possible_agents) if a in env.agents}
                obs[i] = env.step(live)[0]
    assert checked >= 20 * e * n_robots
    assert n_robots == 1 or near > 0  # robots were seen near each other: the bits were checked set too


def test_a_robot_off_the_grid_edge_or_finished_is_no_input():
    inputs = Inputs(3, 3, near_offsets(1))
    cells = np.array([[0, 1, 3, 8]])  # robot 0 in the corner: robots 1 (right) and 2 (below) next to it
    assert inputs.one_hot(inputs.keys(cells, np.array([[True, True, True, True]]))[0, 0])[9:].sum() == 2
    assert inputs.one_hot(inputs.keys(cells, np.array([[True, False, True, True]]))[0, 0])[9:].sum() == 1
    lonely = inputs.keys(np.array([[8, 0]]), np.array([[True, True]]))[0, 0]  # no robot near the far corner
    assert lonely == 8 << 4 and inputs.rows(np.array([lonely])).tolist() == [[8, 13, 13, 13, 13]]


def test_same_seed_same_learning_curve_and_weights():
    def run(seed):
        env = BabyRobotEnv(level="walls")
        cfg = SMALL.replace(eval_every=1024)
        return train_ppo("walls", 1, 4096, seed=seed, config=cfg, evaluate=lambda r: evaluate_single(r.policy(), env, 1).mean)

    a, b, c = run(3), run(3), run(4)
    curve = [(p.timesteps, p.train_return, p.score) for p in a.history]
    assert curve == [(p.timesteps, p.train_return, p.score) for p in b.history] and len(curve) == 4
    for pa, pb in zip(a.net.parameters(), b.net.parameters()):
        assert torch.equal(pa, pb)
    assert any(not torch.equal(pa, pc) for pa, pc in zip(a.net.parameters(), c.net.parameters()))


@pytest.mark.parametrize(("level", "n_robots"), [("maze-8x8", 1), ("race-4", 4)])
def test_save_load_and_act_give_the_same_actions(tmp_path, level, n_robots):
    result = train_ppo(level, n_robots, 4096, seed=1, config=SMALL.replace(n_envs=8))
    path = tmp_path / "policy"  # no suffix: written exactly there
    assert result.save(path) == str(path) and path.is_file()
    back = load_policy(path, BabyRobotEnv(level=level).table)
    trained = result.policy()
    env = race_v0.parallel_env(level=level, n_robots=max(n_robots, 2), start="random")
    seen = 0
    for seed in range(5):
        obs, _ = env.reset(seed=seed)
        for agent_obs in obs.values():
            o = agent_obs[:2] if n_robots == 1 else agent_obs
            assert back(o) == trained(o) and back.act(o) == int(back.predict(o)[0])
            assert np.allclose(back.action_probabilities(o), trained.action_probabilities(o))
            seen += 1
    assert seen >= 10


def test_a_policy_of_another_size_or_a_foreign_file_is_refused(tmp_path):
    result = train_ppo("default", 1, 512, seed=0, config=SMALL.replace(n_envs=4))
    result.save(tmp_path / "p.pt")
    with pytest.raises(ValueError, match=r"policy: .* was trained on default \(3x3\); this level is 5x5"):
        load_policy(tmp_path / "p.pt", BabyRobotEnv(level="walls").table)
    (tmp_path / "text.pt").write_text("not a policy")
    with pytest.raises(ValueError, match="is not a policy saved by 'babyrobot-marl train'"):
        load_policy(tmp_path / "text.pt")
    old = torch.load(tmp_path / "p.pt", weights_only=True)
    del old["observation"]  # a file of version 1 or 2 has no observation field (the global form)
    torch.save({**old, "version": 1}, tmp_path / "v1.pt")  # one robot: version 1 had the same net
    assert load_policy(tmp_path / "v1.pt")(np.array([0, 0])) == result.policy()(np.array([0, 0]))
    torch.save({**old, "version": 1, "n_robots": 2}, tmp_path / "v1-race.pt")
    with pytest.raises(ValueError, match="is a race policy of format version 1 .* train it again"):
        load_policy(tmp_path / "v1-race.pt")
    with pytest.raises(ValueError, match="no such policy file"):
        make_policy(str(tmp_path / "missing.pt"), BabyRobotEnv(level="default").table)
    assert make_policy("shortest", BabyRobotEnv(level="default").table).name == "shortest"


def test_training_runs_on_the_threads_it_is_given_and_restores_torchs_setting():
    before = torch.get_num_threads()
    seen = []
    train_ppo("default", 1, 1024, seed=0, config=SMALL.replace(n_envs=4, threads=1),
              on_update=lambda *_: seen.append(torch.get_num_threads()))
    assert seen and set(seen) == {1} and torch.get_num_threads() == before
    with torch_threads(None):
        assert torch.get_num_threads() == before


@pytest.mark.parametrize(("change", "message"), [
    ({"n_envs": 0}, "n_envs: must be an integer >= 1"),
    ({"batch_size": 2.5}, "batch_size: must be an integer >= 1"),
    ({"gamma": 1.5}, r"gamma: must be a finite number in \[0, 1\]"),
    ({"learning_rate": -1.0}, r"learning_rate: must be a finite number in \[0, inf\]"),
    ({"learning_rate": 0}, "learning_rate: must be a finite number > 0"),
    ({"learning_rate": 10**400}, "learning_rate: must be a finite number"),
    ({"n_envs": np.int64(0)}, "n_envs: must be an integer >= 1"),
    ({"net_arch": (64, 0)}, "net_arch: must be an integer in 1..4096, got 0"),
    ({"start": "corner"}, "start: must be one of 'random', 'level'"),
    ({"threads": True}, "threads: must be an integer >= 1"),
    ({"near_radius": -1}, r"near_radius: must be an integer in 0\.\.4"),
    ({"near_radius": 5}, r"near_radius: must be an integer in 0\.\.4"),
])
def test_bad_settings_are_clear_errors(change, message):
    with pytest.raises(ValueError, match=message):
        PPOConfig().replace(**change)
    with pytest.raises(TypeError, match=r"^replace\(\) got an unexpected keyword argument 'lr'; PPO settings are: .*learning"):
        PPOConfig().replace(lr=0.1)
    with pytest.raises(TypeError, match=r"^train_ppo\(\) got an unexpected keyword argument 'epochs'"):
        train_ppo("default", 1, 10, epochs=2)
    with pytest.raises(ValueError, match="timesteps: must be an integer >= 1"):
        train_ppo("default", 1, 0)
