"""``train`` keeps a user's work: the policy is saved as soon as training ends, a level family's evaluation
fits any documented maze size, and every size, seed and layer limit is checked before training."""

from __future__ import annotations

import json
import re
import shlex

import numpy as np
import pytest

pytest.importorskip("torch", reason="needs the train extra")

from babyrobot_marl.levels import builtin  # noqa: E402
from babyrobot_marl.training.ppo import window  # noqa: E402
from babyrobot_marl.training.ppo.window import Family, stack_levels  # noqa: E402
from tests.cli_run import run  # noqa: E402

TINY = ["--n-envs", "8", "--n-steps", "8", "--batch-size", "64", "--no-progress"]


def cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = run([*argv])
    got = capsys.readouterr()
    return code, got.out, got.err


def one_line_naming(code: int, err: str, flag: str) -> bool:
    return code == 2 and err.count("\n") == 1 and "Traceback" not in err and flag in err


# ---------------------------------------------------------------------------- the policy is saved first
def test_a_maze_too_large_to_stack_by_the_hundred_trains_evaluates_and_saves(tmp_path, capsys):
    """maze-20x20 with 160 evaluation episodes: 160 copies stacked were 20x3359 cells, past the level limit."""
    path = tmp_path / "x.pt"
    code, out, err = cli(capsys, "train", "--level", "maze-20x20", "--observe", "local", "--steps", "1", "--episodes", "160",
                         "--save", str(path), *TINY)
    assert code == 0, err
    assert path.is_file() and f"policy saved to {path}\n" in out
    assert json.loads(out.strip().splitlines()[-1])["episodes"] == 160


def test_the_policy_is_saved_before_the_final_evaluation_which_may_still_fail(tmp_path, capsys, monkeypatch):
    real = window.play_atlas

    def failing_final(net, atlas, n_robots, n_envs, *args, **kwargs):
        if n_envs == 7:  # the final evaluation's --episodes (the evaluations along the way play 64)
            raise RuntimeError("the final evaluation failed")
        return real(net, atlas, n_robots, n_envs, *args, **kwargs)

    monkeypatch.setattr(window, "play_atlas", failing_final)
    path = tmp_path / "x.pt"
    with pytest.raises(RuntimeError, match="the final evaluation failed"):
        run(["train", "--level", "maze:5..6", "--robots", "2", "--observe", "local", "--steps", "1", "--episodes", "7",
             "--save", str(path), *TINY])
    assert f"policy saved to {path}\n" in capsys.readouterr().out
    from babyrobot_marl.training.policy import load_checkpoint

    assert load_checkpoint(path)["observation"]["observe"] == "local"


def test_an_atlas_holds_as_many_mazes_as_the_level_limit_allows():
    from babyrobot_marl.training.ppo.window import atlas_capacity

    assert atlas_capacity(256, 256) == 1 and atlas_capacity(128, 128) == 3 and atlas_capacity(20, 20) == 156
    maze = builtin.get("maze-20x20")
    level, _ = stack_levels([maze] * atlas_capacity(20, 20))  # fits: 20 x 3,275 cells
    assert level.n_cells <= 65_536
    with pytest.raises(ValueError, match="at most 65,536 cells"):
        stack_levels([maze] * (atlas_capacity(20, 20) + 1))


def test_a_family_plays_its_evaluation_in_atlases_that_fit(monkeypatch):
    from babyrobot_marl.levels.sources import EVAL_MAZE_SEEDS, parse_level_family
    from babyrobot_marl.training.ppo import PPOConfig
    from babyrobot_marl.training.ppo.net import make_net

    monkeypatch.setattr(window, "MAX_LEVEL_CELLS", 150)  # 6x6 mazes: three to an atlas
    fam = Family(parse_level_family("maze:6..6", EVAL_MAZE_SEEDS), 2, PPOConfig(), 1, {})
    assert fam.atlas_capacity == 3
    sizes = []
    atlas = Family.atlas

    def spy(self, size):
        got = atlas(self, size)
        sizes.append(len(got.levels))
        return got

    monkeypatch.setattr(Family, "atlas", spy)
    net = make_net(fam.form.n_in, (8,))
    score = fam.play(net, 10, 8, np.random.default_rng(0))
    assert sizes == [3, 3, 3]  # 8 mazes: three atlases of at most 3
    assert set(score) == {"success_rate", "all_reached_rate", "makespan"}
    assert 0 <= score["all_reached_rate"] <= score["success_rate"] <= 1 and 0 < score["makespan"] <= fam.max_steps


# ---------------------------------------------------------------------------- sizes checked before training
@pytest.mark.parametrize("extra", [[], ["--level", "maze:4..4", "--observe", "local"]])
def test_evaluation_episodes_are_checked_before_training_for_one_robot_too(capsys, extra):
    code, out, err = cli(capsys, "train", "--robots", "1", "--episodes", "70000", "--steps", "1", *extra, *TINY)
    assert one_line_naming(code, err, "--episodes") and "trained" not in out


# ---------------------------------------------------------------------------- one seed rule
@pytest.mark.parametrize("argv", [
    ["train", "--steps", "1"], ["train", "--backend", "sb3", "--steps", "1"], ["evaluate", "shortest"], ["race"],
    ["play"], ["solve"],
])
@pytest.mark.parametrize("seed", [str(2**32), str(2**64), "-1"])
def test_every_command_and_backend_takes_seeds_below_2_to_the_32(capsys, argv, seed):
    code, out, err = cli(capsys, *argv, "--seed", seed)
    assert one_line_naming(code, err, "--seed") and "0..4,294,967,295" in err and out == ""


@pytest.mark.parametrize("command", ["train", "evaluate", "race", "play", "solve"])
def test_the_seed_rule_is_stated_in_the_help(capsys, command):
    assert run([command, "--help"]) == 0
    assert "0 <= N < 2**32" in " ".join(capsys.readouterr().out.split())


def test_the_largest_seed_trains(capsys):
    code, out, err = cli(capsys, "train", "--level", "default", "--steps", "1", "--episodes", "2", "--seed", str(2**32 - 1),
                         *TINY)
    assert code == 0, err


# ---------------------------------------------------------------------------- layer sizes
@pytest.mark.parametrize("arch", ["4097", "64,5000", ",".join(["8"] * 9), "1" * 5000])
def test_net_arch_has_an_upper_bound(capsys, arch):
    code, out, err = cli(capsys, "train", "--steps", "1", "--net-arch", arch)
    assert one_line_naming(code, err, "--net-arch") and "1..4,096" in err


def test_a_policy_file_cannot_ask_for_huge_layers(tmp_path):
    import torch

    from babyrobot_marl.training.policy import load_checkpoint
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    with pytest.raises(ValueError, match="net_arch: must be an integer in 1..4096"):
        PPOConfig(net_arch=(8192,))
    path = tmp_path / "p.pt"
    train_ppo("default", 1, 64, seed=0, config=PPOConfig(n_envs=4, n_steps=16, batch_size=64, eval_every=0)).save(path)
    data = torch.load(path, weights_only=True)
    torch.save({**data, "net_arch": [2**20, 2**20]}, tmp_path / "huge.pt")
    with pytest.raises(ValueError, match=r"broken policy file: net_arch: must be a list of up to 8 layer sizes in 1..4,096"):
        load_checkpoint(tmp_path / "huge.pt")


# ---------------------------------------------------------------------------- recommended commands run
def test_the_command_the_gif_refusal_recommends_runs(tmp_path, capsys):
    path = tmp_path / "crowd.pt"
    family = ["--level", "maze:5..6", "--robots", "2", "--observe", "local", "--steps", "1", "--episodes", "2",
              "--save", str(path), *TINY]
    code, out, err = cli(capsys, "train", *family, "--gif", str(tmp_path / "x.gif"))
    assert one_line_naming(code, err, "--gif") and not path.exists()
    recommended = shlex.split(re.search(r"'babyrobot-marl (race [^']*)'", err)[1])
    assert cli(capsys, "train", *family)[0] == 0  # trained without --gif, as it says
    code, out, err = cli(capsys, *recommended, "--seed", "0", "--no-delay")
    assert code == 0, err
    assert str(path) in out


def test_the_command_a_family_without_observe_local_recommends_runs(capsys):
    argv = ["train", "--level", "maze:4..5", "--steps", "1", "--episodes", "2", *TINY]
    code, out, err = cli(capsys, *argv)
    assert one_line_naming(code, err, "--observe") and "pass --observe local" in err
    assert cli(capsys, *argv, "--observe", "local")[0] == 0


def test_the_policy_is_kept_before_the_final_evaluation_that_fails(tmp_path):
    """``on_trained`` runs once training ends, before the final evaluation: a policy saved there survives an
    evaluation that fails (or is interrupted) afterwards."""
    pytest.importorskip("torch")
    from babyrobot_marl.training.policy import load_policy
    from babyrobot_marl.training.ppo import PPOConfig, train_ppo

    path = tmp_path / "kept.pt"
    calls = []

    def evaluate(result):
        calls.append("evaluate")
        raise RuntimeError("the final evaluation failed")

    def on_trained(result):
        calls.append("trained")
        result.save(str(path))

    with pytest.raises(RuntimeError, match="final evaluation failed"):
        train_ppo("maze-8x8", 1, 256, seed=0, config=PPOConfig(n_envs=8, n_steps=16, batch_size=128, eval_every=0),
                  evaluate=evaluate, on_trained=on_trained)
    assert calls == ["trained", "evaluate"]
    assert load_policy(str(path)) is not None
