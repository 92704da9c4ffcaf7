"""The fast trainer under ``finished="stay"`` (POGEMA's ``on_target="nothing"``): the atlas's batch engine keeps
robots racing on their targets, the saved policy records the rule, ``evaluate`` plays it by default, and
``train --finished stay`` is refused by name where it means nothing."""

import json

import numpy as np
import pytest

pytest.importorskip("torch")

from babyrobot_marl import race_v0  # noqa: E402
from babyrobot_marl.core.batch import BatchRace  # noqa: E402
from babyrobot_marl.training.policy import load_checkpoint, load_policy  # noqa: E402
from babyrobot_marl.training.ppo.window import Atlas, WindowForm, play_atlas  # noqa: E402
from tests.cli_run import run  # noqa: E402

CLI_SMALL = ["--n-envs", "16", "--n-steps", "16", "--batch-size", "256", "--no-progress"]
OWN = ["--observe", "local", "--hint", "--goals", "own", "--collisions", "soft"]


def _atlas(stay: bool) -> Atlas:
    from babyrobot_marl.levels import builtin

    levels = [builtin.get("maze-8x8-s1"), builtin.get("maze-10x10-s2")]
    rules = race_v0.parallel_env(level=levels[0], goals="own", start="random", collisions="pass").rules  # no jams
    return Atlas(levels, rules, WindowForm(2, (), True, goals="own"), stay=stay)


def _hint_moves(atlas: Atlas, batch: BatchRace) -> np.ndarray:
    hint = atlas.distances.hint_values(batch.cells, batch.goals)
    return np.where(hint > 0, np.log2(np.maximum(hint & -hint, 1)).astype(np.int64), 0)  # the lowest optimal action; on it: stay


def test_staying_robots_race_on_their_targets_until_all_stand_on_theirs():
    atlas = _atlas(stay=True)
    batch = atlas.batch(20, 3, 200)
    batch.reset_drawn(np.arange(20), np.random.default_rng(0))
    ended_on = np.zeros(20, dtype=bool)
    waited = 0
    while not batch.over.all():
        was = batch.over.copy()
        rewards, finishing, _, _, over = batch.step(_hint_moves(atlas, batch))
        on = batch.cells == batch.goals
        running = ~over
        waited += int((on & running[:, None]).sum())  # on its target, racing on: not finished, reward 0
        assert not finishing[running].any() and (rewards[running][on[running]] == 0).all()
        ended = over & ~was
        assert (finishing[ended] == on[ended]).all()
        ended_on |= ended & on.all(axis=1)
    assert waited > 0 and ended_on.all() and (batch.t < 200).all()  # every race ended with all robots home
    assert batch.racing.all() and (batch.rank > 0).all()  # they finished standing on the board


def test_play_atlas_counts_robots_standing_on_their_targets_at_the_end():
    class Wander:  # a net of even odds: sampled, its robots walk on and off their targets
        recurrent = False

        def actor(self, rows):
            import torch

            return torch.zeros(len(rows), 5)

    n_envs, rng = 64, np.random.default_rng(0)
    score = play_atlas(Wander(), _atlas(stay=True), 3, n_envs, 60, np.random.default_rng(0), deterministic=False)
    batch = _atlas(stay=True).batch(n_envs, 3, 60)  # the same episodes, played by hand with the same draws
    batch.reset_drawn(np.arange(n_envs), rng)
    even = np.cumsum(np.full((n_envs * 3, 5), 0.2, dtype=np.float32), axis=1)
    while not batch.over.all():
        batch.step(np.minimum((rng.random((n_envs * 3, 1)) >= even).sum(axis=1), 4).reshape(n_envs, 3))
    on_now = (batch.cells == batch.goals).mean()
    assert 0 < on_now < 1 and (batch.rank == 0).all()  # some stand on their targets, no race was finished
    assert score["success_rate"] == on_now and score["all_reached_rate"] == 0


def test_the_batch_engine_refuses_stay_without_own_goals_or_with_lifelong():
    env = race_v0.parallel_env(level="race-4", n_robots=2)
    with pytest.raises(ValueError, match=r"^stay: "):
        BatchRace(env.table, 2, 2, 10, free=env._free, start="random", stay=True)
    own = race_v0.parallel_env(level="race-4", n_robots=2, goals="own", lifelong=True, start="random")
    with pytest.raises(ValueError, match=r"^stay: "):
        BatchRace(own.table, 2, 2, 10, free=own._free, start="random", goal_columns=own._goal_columns, lifelong=True,
                  stay=True)


@pytest.mark.parametrize(("extra", "got"), [
    (["--finished", "stay", "--observe", "local"], "--goals exit"),
    (["--finished", "stay", *OWN, "--lifelong"], "--lifelong"),
])
def test_train_refuses_finished_stay_by_name_before_training(extra, got, capsys, monkeypatch):
    from babyrobot_marl.training.ppo import loop

    monkeypatch.setattr(loop, "train_ppo", lambda *a, **k: pytest.fail("training started"))
    assert run(["train", "--level", "maze:8..10", "--robots", "4", "--steps", "1000", *extra]) == 2
    err = capsys.readouterr().err
    assert err.splitlines() == [
        f"babyrobot-marl: error: --finished: 'stay' keeps robots on their own targets (--goals own, no --lifelong), "
        f"got {got}"]


def test_a_short_staying_run_saves_its_rule_and_evaluate_plays_it_by_default(tmp_path, capsys):
    path = tmp_path / "stay.pt"
    argv = ["train", "--level", "maze:8..10", "--robots", "4", *OWN, "--finished", "stay", "--steps", "4096",
            "--episodes", "16", "--save", str(path), *CLI_SMALL]
    assert run(argv) == 0
    out = capsys.readouterr().out
    assert "own goals, finished stay, collisions soft" in out
    assert load_checkpoint(str(path))["env"] == {"goals": "own", "collisions": "soft", "lifelong": False,
                                                  "finished": "stay"}
    evaluate = ["evaluate", str(path), "--level", "maze:8..10", "--robots", "4", "--episodes", "8", "--collisions", "soft"]
    figures = {}
    for rule in (None, "stay", "remove"):
        assert run(evaluate + ([] if rule is None else ["--finished", rule])) == 0
        shown = capsys.readouterr().out.splitlines()
        figures[rule] = json.loads(shown[-1])
        assert ("robots stayed on their targets (--finished stay)" in shown[-2]) and figures[rule]
    assert figures[None] == figures["stay"] != figures["remove"]  # left out: the policy's own rule


def test_a_policy_file_from_before_the_rule_loads_and_evaluates_with_robots_leaving(tmp_path, capsys):
    import torch

    path = tmp_path / "old.pt"
    argv = ["train", "--level", "maze:8..10", "--robots", "4", *OWN, "--steps", "2048", "--episodes", "4",
            "--save", str(path), *CLI_SMALL]
    assert run(argv) == 0
    capsys.readouterr()
    data = load_checkpoint(str(path))
    assert data["env"]["finished"] == "remove"
    del data["env"]["finished"]  # as files were written before the rule was recorded
    torch.save(data, path)
    env = race_v0.parallel_env(level="maze:8..10", n_robots=4, observe="local", hint=True, start="random",
                               goals="own", collisions="soft")
    obs, _ = env.reset(seed=0)
    assert load_policy(str(path), env=env)(obs["robot_0"]) in range(5)
    evaluate = ["evaluate", str(path), "--level", "maze:8..10", "--robots", "4", "--episodes", "4", "--collisions", "soft"]
    assert run(evaluate) == 0
    left_out = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert run(evaluate + ["--finished", "remove"]) == 0
    assert json.loads(capsys.readouterr().out.splitlines()[-1]) == left_out
    data["env"]["finished"] = "sit"
    torch.save(data, path)
    with pytest.raises(ValueError, match=r"is a broken policy file: env: .*'finished': one of \('remove', 'stay'\)"):
        load_checkpoint(str(path))
