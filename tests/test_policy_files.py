"""Saved policies from elsewhere (issue 24, items 2-6 and 9), and the train command's figures (issue 23, item 5).

A saved policy reads the observation form it was trained on, or an env's form through ``for_env``,
or refuses it by name; a broken policy file is one error line from every command that reads one;
``train`` checks every argument before it trains, refuses a run that diverged, and names its
wall-clock and CPU-time speeds.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

torch = pytest.importorskip("torch", reason="the train extra is not installed")  # CI installs it (test extra)

from babyrobot_marl import BabyRobotEnv, cli, race_v0  # noqa: E402
from babyrobot_marl.envs.encodings import Encoder  # noqa: E402
from babyrobot_marl.training.deps import TORCH_CPU  # noqa: E402
from babyrobot_marl.training.policy import load_checkpoint, load_policy  # noqa: E402
from babyrobot_marl.training.ppo import PPOConfig, TrainingDivergedError, train_ppo  # noqa: E402
from tests.cli_run import run  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
TINY = PPOConfig(n_envs=8, n_steps=16, batch_size=128, eval_every=0)
SMALL = ["--n-envs", "16", "--n-steps", "16", "--batch-size", "128", "--eval-every", "512"]


def one_error_line(err: str) -> str:
    assert "Traceback" not in err and err.count("\n") == 1, err
    return err


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, Path]:
    """A one-robot policy on walls (5x5) and a race policy on race-4 (near_radius 1), saved."""
    folder = tmp_path_factory.mktemp("policies")
    single, race = folder / "single.pt", folder / "race.pt"
    train_ppo("walls", 1, 1024, seed=0, config=TINY).save(single)
    train_ppo("race-4", 4, 2048, seed=0, config=TINY).save(race)
    return {"single": single, "race": race}


# ---------------------------------------------------------------------------- item 2: the observation form
def test_the_file_records_the_observation_form_it_was_trained_on(files):
    data = load_checkpoint(files["race"])
    assert data["observation"] == {"observe": "global", "obs_encoding": "multidiscrete", "hint": False}
    assert data["config"]["near_radius"] == 1 and data["version"] == 4


@pytest.mark.parametrize("encoding", ["onehot", "box"])
def test_a_one_robot_policy_reads_another_encoding_through_for_env_and_refuses_it_unbound(files, encoding):
    policy = load_policy(files["single"])
    env = BabyRobotEnv(level="walls", obs_encoding=encoding)
    bound = load_policy(files["single"], env=env)
    encode = Encoder([5, 5], encoding)
    actions = set()
    for y in range(5):
        for x in range(5):
            plain = np.array([x, y])
            assert bound(encode(plain)) == policy(plain)  # every cell gets its own action
            assert np.allclose(bound.action_probabilities(encode(plain)), policy.action_probabilities(plain))
            actions.add(policy(plain))
    # unbound, the policy refuses what is not its form instead of reading the first two numbers as x, y
    obs, _ = env.reset(seed=0)
    with pytest.raises(ValueError, match=r"obs: this policy reads observe='global', obs_encoding='multidiscrete'.*for_env"):
        policy(obs)


def _keys(policy, env_kwargs, seeds=range(6), steps=25):
    """The keys a policy reads from the same race states under an env's observation settings."""
    env = race_v0.parallel_env(level="race-4", n_robots=4, start="random", **env_kwargs)
    bound = policy.for_env(env)
    rng = np.random.default_rng(0)
    keys = []
    for seed in seeds:
        obs, _ = env.reset(seed=seed)
        for _ in range(steps):
            keys += [bound.decoder(obs[a]) for a in env.agents]
            if not env.agents:
                break
            obs, *_ = env.step({a: int(rng.integers(5)) for a in env.agents})
    return keys


@pytest.mark.parametrize("settings", [{"observe": "local", "view_radius": 1}, {"observe": "local"},
                                      {"observe": "nearest", "k": 3}, {"obs_encoding": "onehot"},
                                      {"observe": "local", "view_radius": 2, "obs_encoding": "onehot"},
                                      {"observe": "nearest", "k": 3, "obs_encoding": "box"}])
def test_a_race_policy_reads_the_local_and_nearest_views_that_hold_what_it_sees(files, settings):
    policy = load_policy(files["race"])
    reference = _keys(policy, {})
    assert _keys(policy, settings) == reference
    assert sum(k & 0b1111 != 0 for k in reference) >= 10  # robots next to each other: the near bits are read


@pytest.mark.parametrize(("settings", "message"), [
    ({"observe": "nearest", "k": 2}, r"observe='nearest' k=2 of 3 other robots .* use k >= 3"),
    ({"observe": "local", "view_radius": 0}, r"observe='local' view_radius=0 shows fewer: use view_radius >= 1"),
])
def test_a_race_policy_refuses_a_view_that_can_hide_a_robot_it_sees(files, settings, message):
    env = race_v0.parallel_env(level="race-4", n_robots=4, **settings)
    with pytest.raises(ValueError, match=message):
        load_policy(files["race"], env=env)


def test_an_unbound_race_policy_refuses_nearest_rows_instead_of_numpys_reshape_error(files):
    env = race_v0.parallel_env(level="race-4", n_robots=4, observe="nearest", k=2)
    obs, _ = env.reset(seed=0)
    with pytest.raises(ValueError, match="obs: this policy reads observe='global'.* got 6 int64 numbers; bind it"):
        load_policy(files["race"])(obs["robot_0"])


def test_play_and_race_read_their_envs_form(files, capsys):
    argv = ["race", "--level", "race-4", "--robots", "4", "--policies", f"{files['race']},shortest,random,random",
            "--seed", "1", "--no-delay"]
    assert run(argv) == 0
    assert str(files["race"]) in capsys.readouterr().out


# ---------------------------------------------------------------------------- item 3: broken files
def _broken(data: dict) -> dict[str, dict]:
    sd = data["state_dict"]
    arch = data["net_arch"]

    def without(key):
        return {k: v for k, v in data.items() if k != key}

    def weights(**changes):
        return {**data, "state_dict": {**sd, **changes}}

    return {
        "missing state_dict": without("state_dict"),
        "missing config": without("config"),
        "missing n_robots": without("n_robots"),
        "missing observation": without("observation"),
        "unknown field": {**data, "extra": 1},
        "width 0": {**data, "width": 0},
        "width text": {**data, "width": "5"},
        "n_robots 0": {**data, "n_robots": 0},
        "net_arch text": {**data, "net_arch": ["x"]},
        "net_arch other sizes": {**data, "net_arch": [32, 32]},
        "near_radius 50": {**data, "config": {**data["config"], "near_radius": 50}},
        "config list": {**data, "config": [1]},
        "observation local": {**data, "observation": {"observe": "local", "obs_encoding": "multidiscrete"}},
        "tensor size": weights(**{"actor.first_bias": torch.zeros(arch[0] + 1)}),
        "tensor dtype": weights(**{"actor.first_bias": sd["actor.first_bias"].double()}),
        "tensor missing": {**data, "state_dict": {k: v for k, v in sd.items() if k != "critic.first"}},
        "tensor not a tensor": weights(**{"critic.first_bias": [0.0] * arch[0]}),
        "NaN weights": weights(**{"actor.layers.0.weight": torch.full_like(sd["actor.layers.0.weight"], float("nan"))}),
        "level not text": {**data, "level": 5},
        "timesteps -1": {**data, "timesteps": -1},
    }


@pytest.fixture(scope="module")
def broken_files(files, tmp_path_factory) -> list[Path]:
    folder = tmp_path_factory.mktemp("broken")
    data = torch.load(files["race"], weights_only=True)
    paths = []
    for name, body in _broken(data).items():
        path = folder / (name.replace(" ", "_") + ".pt")
        torch.save(body, path)
        paths.append(path)
    return paths


@pytest.mark.parametrize("command", ["play", "train", "race"])
def test_every_broken_field_is_one_error_line_and_status_2_from_every_command(broken_files, command, capsys):
    for path in broken_files:
        argv = {"play": ["play", "--level", "race-4", "--policy", str(path), "--no-delay"],
                "train": ["train", "--level", "race-4", "--robots", "4", "--steps", "256", "--load", str(path), *SMALL],
                "race": ["race", "--level", "race-4", "--policies", f"{path},shortest,shortest,shortest", "--no-delay"]}[command]
        assert run(argv) == 2, path.name
        captured = capsys.readouterr()
        flag = {"play": "--policy", "train": "--load", "race": "--policies"}[command]  # the command's own flag
        assert f"{flag}: {str(path)!r}" in one_error_line(captured.err), path.name
        assert "steps" not in captured.out  # refused before anything ran


def test_a_plain_pickle_is_one_line_without_torchs_warning(tmp_path):
    path = tmp_path / "plain.pkl"
    path.write_bytes(__import__("pickle").dumps({"format": "babyrobot_marl.ppo"}, protocol=4))
    done = subprocess.run([sys.executable, "-m", "babyrobot_marl", "play", "--policy", str(path), "--no-delay"],
                          capture_output=True, text=True, cwd=ROOT, env=_env(), timeout=300)
    assert done.returncode == 2
    assert one_error_line(done.stderr).startswith(f"babyrobot-marl: error: --policy: {str(path)!r} is not a policy saved by")


# ---------------------------------------------------------------------------- item 4: race --races, no torch
def test_race_with_races_takes_a_saved_policy(files, capsys):
    argv = ["race", "--level", "race-4", "--robots", "4", "--races", "3", "--seed", "0",
            "--policies", f"{files['race']},shortest,random,random"]
    assert run(argv) == 0
    out = capsys.readouterr().out
    assert out.startswith("3 races on race-4") and f"robot_0  {files['race']}" in out


def _env() -> dict:
    import os

    return {**os.environ, "PYTHONPATH": str(ROOT)}


def test_play_with_a_saved_policy_without_torch_is_one_line_naming_the_cpu_route(files):
    blocker = textwrap.dedent("""
        import importlib.abc, sys

        class NoTorch(importlib.abc.MetaPathFinder):  # as if torch were not installed
            def find_spec(self, name, path=None, target=None):
                if name == "torch" or name.startswith("torch."):
                    raise ModuleNotFoundError(f"No module named {name!r}", name=name)
                return None

        sys.meta_path.insert(0, NoTorch())
        from babyrobot_marl.cli import main
        sys.exit(main(sys.argv[1:]))
    """)
    done = subprocess.run([sys.executable, "-c", blocker, "play", "--level", "walls", "--policy", str(files["single"]),
                           "--no-delay"], capture_output=True, text=True, cwd=ROOT, env=_env(), timeout=300)
    assert done.returncode == 2
    line = one_error_line(done.stderr)
    assert "torch" in line and TORCH_CPU in line and "pip install 'babyrobot_marl[train]'" in line


def test_every_install_hint_of_the_train_extra_gives_the_torch_first_cpu_route(capsys):
    from babyrobot_marl.training import MissingTrainExtraError, require_train

    with pytest.raises(MissingTrainExtraError) as err:
        require_train("babyrobot_marl_no_such_module")
    assert TORCH_CPU in str(err.value) and TORCH_CPU == "pip install torch==2.13.0 --index-url https://download.pytorch.org/whl/cpu"
    with pytest.raises(SystemExit):
        cli.main(["train", "--help"])
    assert TORCH_CPU in " ".join(capsys.readouterr().out.split())
    import babyrobot_marl.training as training

    assert TORCH_CPU in " ".join(training.__doc__.split())


# ---------------------------------------------------------------------------- item 5: divergence
def test_a_diverging_run_raises_and_the_cli_saves_nothing(tmp_path, capsys):
    with pytest.raises(TrainingDivergedError, match="learning_rate: training diverged"):
        train_ppo("default", 1, 4096, seed=0, config=TINY.replace(learning_rate=1e30))
    saved = tmp_path / "p.pt"
    assert run(["train", "--level", "default", "--steps", "4096", "--lr", "1e30", "--save", str(saved), *SMALL]) == 2
    err = one_error_line(capsys.readouterr().err)
    assert "--lr 1e+30: training diverged" in err and "nothing was saved" in err
    assert not saved.exists()


# ---------------------------------------------------------------------------- item 6 and 9: checked before training
@pytest.mark.parametrize(("argv", "message"), [
    (["--save", "/no/such/folder/p.pt"], "--save: no such folder '/no/such/folder'"),
    (["--curve", "/no/such/folder/c.png"], "--curve: no such folder"),
    (["--level", "race-4", "--robots", "4", "--episodes", "70000"], "--episodes: a batch holds at most 65,536 envs"),
    (["--n-envs", "70000"], "--n-envs: a batch holds at most 65,536 envs"),
    (["--robots", "1", "--near-radius", "3"], "--near-radius: a lone robot (--robots 1) sees no other robot"),
    (["--level", "race-4", "--robots", "4", "--near-radius", "5"], "--near-radius: must be an integer in 0..4"),
    (["--lr", "nan"], "--lr: must be a number > 0"),
    (["--ent-coef", "-1"], "--ent-coef: must be a number >= 0"),
])
def test_bad_train_arguments_are_refused_by_flag_before_training(argv, message, tmp_path, capsys):
    assert run(["train", "--steps", "2048", *argv]) == 2
    captured = capsys.readouterr()
    assert message in one_error_line(captured.err)
    assert captured.out == ""  # nothing trained


def test_a_rounded_step_count_is_said_in_one_line_and_the_figures_name_wall_and_cpu_time(capsys):
    assert run(["train", "--level", "default", "--steps", "1000", "--no-progress", *SMALL]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert lines[0] == ("--steps 1,000: training runs whole rollouts of 256 timesteps (--n-envs 16 x --n-steps 16), "
                        "so 1,024 timesteps")
    figures = json.loads(lines[-1])
    assert figures["timesteps"] == 1024
    # seconds are rounded to 0.1 ms in the JSON (a run of 1,024 steps takes a few ms): compare at that precision
    assert figures["timesteps"] / figures["env_steps_per_second"] == pytest.approx(figures["seconds"], abs=1e-4)
    assert figures["timesteps"] / figures["env_steps_per_cpu_second"] == pytest.approx(figures["cpu_seconds"], abs=1e-4)
    speed = [line for line in lines if line.startswith("trained 1,024 timesteps in ")]
    assert len(speed) == 1 and " s wall-clock (" in speed[0] and " env steps/s of CPU time)" in speed[0]
    assert run(["train", "--level", "default", "--steps", "1024", "--no-progress", *SMALL]) == 0
    assert "--steps" not in capsys.readouterr().out  # nothing rounded: nothing said
