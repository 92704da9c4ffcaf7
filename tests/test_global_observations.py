"""The "global" rows of the batch engine (``observe.global_observations``) and the arrays they are
written into (``observe.Recycler``): the same numbers as the docstring says and as the index
gather they replace, and an array a caller keeps is never written again."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from babyrobot_marl import race_v0
from babyrobot_marl.core.observe import Recycler, global_gather, global_observations
from babyrobot_marl.envs.vector import RaceVectorEnv


def reference_rows(xyf: np.ndarray) -> np.ndarray:
    """From the docstring, one number at a time: robot i's [x, y], then [x, y, finished] of
    robots i+1, ..., n-1, 0, ..., i-1 (race_v0's order)."""
    *lead, n, _ = xyf.shape
    races = xyf.reshape(-1, n, 3)
    out = []
    for race in races:
        rows = []
        for i in range(n):
            row = [race[i, 0], race[i, 1]]
            for j in [*range(i + 1, n), *range(i)]:
                row += [race[j, 0], race[j, 1], race[j, 2]]
            rows.append(row)
        out.append(rows)
    return np.array(out, dtype=np.int64).reshape(*lead, n, 3 * n - 1)


def random_state(rng: np.random.Generator, lead: tuple[int, ...], n: int, finished: str) -> np.ndarray:
    xyf = np.empty((*lead, n, 3), dtype=np.int64)
    xyf[..., 0] = rng.integers(0, 64, (*lead, n))
    xyf[..., 1] = rng.integers(0, 48, (*lead, n))
    flags = {
        "none": np.zeros((*lead, n), dtype=bool),
        "all": np.ones((*lead, n), dtype=bool),
        "alternate": np.broadcast_to(np.arange(n) % 2 == 1, (*lead, n)),
        "random": rng.random((*lead, n)) < 0.3,
    }[finished]
    xyf[..., 2] = flags
    return xyf


# both sides of the switch from the index gather to windows (observe._WINDOWS_FROM = 24)
@pytest.mark.parametrize("n", [1, 2, 3, 7, 23, 24, 25, 64, 130])
@pytest.mark.parametrize("lead", [(), (1,), (3,), (2, 2)])
@pytest.mark.parametrize("finished", ["none", "all", "alternate", "random"])
def test_global_rows_equal_the_docstring_reference(n, lead, finished):
    rng = np.random.default_rng([n, len(lead), hash(finished) % 1000])
    xyf = random_state(rng, lead, n, finished)
    rows = global_observations(xyf)
    assert rows.dtype == np.int64 and rows.shape == (*lead, n, 3 * n - 1)
    np.testing.assert_array_equal(rows, reference_rows(xyf))


@pytest.mark.parametrize("n", [1, 2, 5, 23, 24, 100])
def test_global_rows_equal_the_index_gather_they_replace(n):
    xyf = random_state(np.random.default_rng(n), (4,), n, "random")
    old = xyf.reshape(4, -1).take(global_gather(n), axis=1)
    np.testing.assert_array_equal(global_observations(xyf), old)


@pytest.mark.parametrize("n", [2, 80])
def test_global_rows_are_written_into_out_and_a_wrong_out_is_refused(n):
    xyf = random_state(np.random.default_rng(0), (3,), n, "random")
    out = np.full((3, n, 3 * n - 1), -1, dtype=np.int64)
    assert global_observations(xyf, out) is out
    np.testing.assert_array_equal(out, reference_rows(xyf))
    wrong_shape, wrong_dtype = np.empty((3, n, 3 * n), np.int64), np.empty((3, n, 3 * n - 1), np.int32)
    not_contiguous = np.empty((3, 3 * n - 1, n), np.int64).swapaxes(1, 2)
    for bad in (wrong_shape, wrong_dtype, not_contiguous):
        with pytest.raises(ValueError, match="out"):
            global_observations(xyf, bad)


@pytest.mark.parametrize(("n_envs", "n_robots"), [(1, 1), (3, 2), (2, 5), (2, 70)])
def test_batch_global_rows_equal_each_single_race(n_envs, n_robots):
    """Env i of the batch observes what race_v0 (finished="freeze") seeded alike observes, finished robots included."""
    kw = dict(level="maze-16x16", n_robots=n_robots, start="random", finished="freeze")
    batch = race_v0.parallel_env(**kw).batch(n_envs)
    batch.seed(range(n_envs))
    batch.reset_envs(range(n_envs))
    envs = [race_v0.parallel_env(**kw) for _ in range(n_envs)]
    for i, env in enumerate(envs):
        env.reset(seed=i)
    rng = np.random.default_rng(1)
    for _ in range(60):
        actions = rng.integers(0, 5, (n_envs, n_robots))
        _, _, _, _, over = batch.step(actions)
        rows = batch.observations()
        for i, env in enumerate(envs):
            if not env.agents:
                continue
            obs, *_ = env.step({a: int(actions[i, k]) for k, a in enumerate(env.possible_agents) if a in env.agents})
            for k, agent in enumerate(env.possible_agents):
                if agent in obs:
                    np.testing.assert_array_equal(rows[i, k], obs[agent])
        if over.all():
            break


# ------------------------------------------------------------------------ recycled arrays
@pytest.fixture
def recycle_all(monkeypatch):
    """Recycle arrays of any size (the real threshold is 32 MB)."""
    monkeypatch.setattr(Recycler, "RECYCLE_FROM", 0)


def test_an_array_nobody_holds_is_handed_out_again(recycle_all):
    r = Recycler()
    first = r.empty((3, 4))
    address = first.ctypes.data
    del first
    again = r.empty((3, 4))
    assert again.ctypes.data == address


@pytest.mark.parametrize("hold", ["array", "view", "row", "memoryview", "in a list"])
def test_an_array_a_caller_holds_in_any_form_is_never_handed_out_again(recycle_all, hold):
    r = Recycler()
    a = r.empty((3, 4))
    a[...] = 7
    if hold == "array":
        kept = a
    elif hold == "view":
        kept = a.reshape(-1)
    elif hold == "row":
        kept = a[1]
    elif hold == "memoryview":
        kept = memoryview(a)
    else:
        kept = [a]
    address = a.ctypes.data
    del a
    for _ in range(5):
        b = r.empty((3, 4))
        assert b.ctypes.data != address
        b[...] = 0
    assert np.all(np.asarray(kept if hold != "in a list" else kept[0]) == 7)


def test_small_arrays_and_other_interpreters_always_get_new_arrays(monkeypatch):
    r = Recycler()
    for _ in range(3):
        r.empty((3, 4))  # under the threshold: a new array each time, nothing held
    assert r._held == []
    monkeypatch.setattr(Recycler, "RECYCLE_FROM", 0)
    off = Recycler()
    off._on = False  # as without reference counts
    for _ in range(3):
        off.empty((3, 4))
    assert off._held == []


def test_the_batch_never_overwrites_observations_the_caller_keeps(recycle_all):
    env = race_v0.parallel_env(level="maze-16x16", n_robots=70, start="random")
    batch = env.batch(2)
    batch.seed([0, 1])
    batch.reset_envs([0, 1])
    rng = np.random.default_rng(0)
    kept, copies, addresses = [], [], set()
    for t in range(8):
        batch.step(rng.integers(0, 5, (2, 70)))
        obs = batch.observations()
        addresses.add(obs.ctypes.data)
        if t % 2:  # keep every other step's
            kept.append(obs)
            copies.append(obs.copy())
        del obs
    assert all(np.array_equal(k, c) for k, c in zip(kept, copies))
    assert len(addresses) < 8  # the dropped ones were recycled


def test_vector_env_observations_kept_across_steps_stay_as_returned(recycle_all):
    """Gymnasium's vector envs return arrays the caller owns (SyncVectorEnv copies by default)."""
    env = RaceVectorEnv(2, level="maze-16x16", n_robots=70, start="random")
    obs, _ = env.reset(seed=0)
    history, copies = [obs], [obs.copy()]
    rng = np.random.default_rng(0)
    for _ in range(6):
        obs, *_ = env.step(rng.integers(0, 5, env.num_envs))
        history.append(obs)
        copies.append(obs.copy())
    assert all(np.array_equal(h, c) for h, c in zip(history, copies))
    assert len({h.ctypes.data for h in history}) == len(history)


def test_at_the_real_threshold_the_batch_recycles_and_kept_arrays_survive():
    """2 envs x 1,000 robots: 48 MB of rows a step, past Recycler.RECYCLE_FROM."""
    env = race_v0.parallel_env(level="maze-64x64", n_robots=1000, start="random")
    batch = env.batch(2)
    assert Recycler.RECYCLE_FROM < 2 * 1000 * 2999 * 8
    batch.seed([0, 1])
    batch.reset_envs([0, 1])
    kept = batch.observations()
    copy = kept.copy()
    rng = np.random.default_rng(0)
    addresses = set()
    for _ in range(4):
        batch.step(rng.integers(0, 5, (2, 1000)))
        addresses.add(batch.observations().ctypes.data)  # dropped at once
    assert np.array_equal(kept, copy) and kept.ctypes.data not in addresses
    assert len(addresses) == 1


def test_a_pickled_batch_carries_no_spare_arrays_and_still_recycles(recycle_all):
    batch = race_v0.parallel_env(level="maze-16x16", n_robots=30, start="random").batch(2)
    batch.seed([0, 1])
    batch.reset_envs([0, 1])
    batch.observations()
    assert len(batch._recycler._held) == 1
    copy = pickle.loads(pickle.dumps(batch))
    assert copy._recycler._held == []
    first = copy.observations()
    address = first.ctypes.data
    np.testing.assert_array_equal(first, batch.observations())
    del first
    assert copy.observations().ctypes.data == address
