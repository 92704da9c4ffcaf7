"""Size limits (README "Limits"), checked before anything large is allocated, and the level-text
edges of issue 15: whitespace lines, CR line ends, rewards too large for a float."""

from __future__ import annotations

import tracemalloc
from functools import partial

import pytest

from babyrobot_marl import Level, levels, race_v0
from babyrobot_marl.core.checks import MAX_DENSE_STATES, MAX_LEVEL_CELLS, MAX_LEVEL_TEXT_CHARS
from babyrobot_marl.core.rules import Rules
from babyrobot_marl.levels.resolve import resolve_level
from babyrobot_marl.planning import model, value_iteration
from babyrobot_marl.render.checks import check_frame_pixels, max_cell_size

TINY = "+-+-+\n|S E|\n+-+-+"


def corridor(n: int) -> str:
    """A one-row corridor of ``n`` cells: start at the left end, exit at the right end."""
    return "\n".join(["+" + "-+" * n, "|S" + " " * (2 * n - 3) + "E|", "+" + "-+" * n])


def peak_bytes(fn) -> int:
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


# ------------------------------------------------------------------------ level size
def test_the_largest_maze_is_within_the_level_size_limit():
    assert MAX_LEVEL_CELLS >= 256 * 256
    assert levels.get("maze-256x256").n_cells == 65_536


def test_a_one_row_corridor_of_the_limits_length_is_allowed():
    level = Level.from_ascii(corridor(MAX_LEVEL_CELLS))
    assert (level.width, level.height) == (MAX_LEVEL_CELLS, 1)


def test_the_longest_level_text_with_crlf_line_ends_and_an_indent_is_within_the_character_limit():
    """A one-column corridor of 65,536 cells has the most lines (131,073): indented by 2, with CRLF."""
    rows = ["+-+", "|S|"] + ["+ +", "| |"] * (MAX_LEVEL_CELLS - 2) + ["+ +", "|E|", "+-+"]
    text = "\r\n".join("  " + row for row in rows)
    assert len(text) <= MAX_LEVEL_TEXT_CHARS
    level = Level.from_ascii(text)
    assert (level.width, level.height) == (1, MAX_LEVEL_CELLS)


def test_a_level_one_cell_past_the_limit_is_refused_by_name():
    with pytest.raises(ValueError, match=r"width, height: a level has at most 65,536 cells.*65537x1"):
        Level(width=MAX_LEVEL_CELLS + 1, height=1, exits=[(0, 0)])


def test_a_text_past_the_cell_limit_is_refused_before_it_is_parsed():
    """The 257x256 text ends in a bad character: the size error comes first, so no cell was parsed."""
    text = "\n".join(["+" + "-+" * 257] + ["|" + " |" * 257, "+" + "-+" * 257] * 256)
    text = text[:-1] + "?"
    with pytest.raises(ValueError, match="text: a level has at most 65,536 cells") as info:
        Level.from_ascii(text)
    assert "bad character" not in str(info.value)


def test_a_text_past_the_character_limit_is_refused_before_it_is_split():
    text = TINY + "\n" + " " * MAX_LEVEL_TEXT_CHARS
    assert peak_bytes(lambda: pytest.raises(ValueError, Level.from_ascii, text)) < 2**20


# ------------------------------------------------------------------------ dense model
def test_the_dense_model_past_its_limit_names_the_limit_and_the_sparse_alternative():
    m = model("maze-256x256")
    holder = {}

    def ask():
        with pytest.raises(ValueError) as info:
            _ = m.P
        holder["message"] = str(info.value)

    assert peak_bytes(ask) < 2**20  # refused before the 172 GB array
    message = holder["message"]
    assert f"at most {MAX_DENSE_STATES:,} states" in message and "65,536" in message
    assert "sparse" in message and "model.next" in message
    assert value_iteration(model("maze-16x16")).iterations > 0  # the sparse path all planning uses


def test_the_core_dense_arrays_past_the_limit_are_refused_before_allocating():
    from babyrobot_marl.core import compile_level, transition_arrays

    table = compile_level(levels.get("maze-128x128"))
    with pytest.raises(ValueError, match="transition_arrays: the dense model holds at most"):
        transition_arrays(table)


def test_the_dense_model_within_its_limit_is_built():
    m = model("maze-16x16")
    assert m.P.shape == (256, 5, 256)


# ------------------------------------------------------------------------ frames (helper for the renderer)
def test_frame_pixels_past_the_limit_are_refused_naming_cell_size_and_the_way_out():
    with pytest.raises(ValueError, match="cell_size: .* more than the limit .* use a smaller cell_size"):
        check_frame_pixels(256 * 256, 256 * 256)
    check_frame_pixels(1000, 1000)


def test_max_cell_size_is_the_largest_size_whose_frame_fits():
    size = max_cell_size(256, 256, extra_height_px=40)
    check_frame_pixels(size * 256, size * 256 + 40)
    with pytest.raises(ValueError):
        check_frame_pixels((size + 1) * 256, (size + 1) * 256 + 40)


# ------------------------------------------------------------------------ caches
def test_the_maze_cache_is_bounded_whatever_sizes_and_seeds_are_asked_for():
    for seed in range(20):
        levels.get(f"maze-4x4-s{seed}")
    info = levels._maze.cache_info()
    assert info.maxsize is not None and info.currsize <= info.maxsize <= 16


# ------------------------------------------------------------------------ whitespace and line ends
@pytest.mark.parametrize("char", ["\f", "\v", "\t", "\x1c", "\xa0", "\u3000"])
def test_a_level_line_made_only_of_a_whitespace_character_is_an_error_like_inside_a_line(char):
    inside = "+-+-+\n|S E|\n+" + char + "+ +\n|   |\n+-+-+"
    alone = "+-+-+\n|S E|\n" + char + "\n|   |\n+-+-+"
    for text in (inside, alone):
        with pytest.raises(ValueError, match=r"line 3, column \d+: bad character " + repr(char).replace("\\", "\\\\")):
            Level.from_ascii(text)


def test_a_trailing_form_feed_is_a_character_not_trimmed_whitespace():
    with pytest.raises(ValueError, match="line 2"):
        Level.from_ascii("+-+-+\n|S E|\f\n+-+-+")


def test_trailing_spaces_and_blank_lines_of_spaces_and_tabs_around_the_level_are_still_allowed():
    assert Level.from_ascii(" \t\n\n+-+-+   \n|S E|\n+-+-+  \n\t\n") == Level.from_ascii(TINY)


@pytest.mark.parametrize("sep", ["\r", "\r\n", "\n"])
def test_cr_crlf_and_lf_line_ends_read_the_same_level(sep):
    assert Level.from_ascii(TINY.replace("\n", sep)) == Level.from_ascii(TINY)


def test_a_cr_only_level_text_given_to_an_env_is_a_level_not_a_name():
    level = resolve_level(TINY.replace("\n", "\r"))
    assert (level.width, level.height, level.starts) == (2, 1, ((0, 0),))


# ------------------------------------------------------------------------ rewards too large for a float
@pytest.mark.parametrize("field", ["floor_reward", "exit_reward", "win_bonus", "glass_pass_prob"])
def test_a_rule_too_large_for_a_float_is_a_value_error_naming_the_field(field):
    with pytest.raises(ValueError, match=f"^{field}: must be a finite number"):
        Rules(**{field: 10**400})


def test_a_custom_reward_too_large_for_a_float_is_a_value_error_naming_rewards():
    level = Level.from_ascii(TINY)
    with pytest.raises(ValueError, match="^rewards: a reward must be a finite number"):
        level.with_rewards({(0, 0): 10**400})
    with pytest.raises(ValueError, match="^rewards: a reward must be a finite number"):
        level.with_rewards({(0, 0): -(10**400)})
    assert level.with_rewards({(0, 0): 10**300}).reward_map() == {(0, 0): 1e300}  # a big int that fits a float


# ------------------------------------------------------------------------ batch engine and vector envs
def test_a_vector_env_of_a_billion_envs_is_refused_by_name_before_anything_per_env_exists():
    from babyrobot_marl.core.checks import MAX_BATCH_ENVS
    from babyrobot_marl.envs.vector import BabyRobotVectorEnv, RaceVectorEnv

    for make, name in ((RaceVectorEnv, "n_envs"), (BabyRobotVectorEnv, "num_envs")):
        with pytest.raises(ValueError, match=rf"^{name}: a batch holds at most {MAX_BATCH_ENVS:,} envs") as err:
            make(10**9)
        assert "got 1,000,000,000" in str(err.value)
        assert peak_bytes(lambda make=make: pytest.raises(ValueError, make, 10**9)) < 2**20  # refused before the env is built


def test_the_batch_engine_itself_refuses_too_many_envs_and_non_integers():
    env = race_v0.parallel_env(level="race-4", n_robots=2)
    with pytest.raises(ValueError, match="n_envs: a batch holds at most"):
        env.batch(10**9)
    for bad in (0, 2.0, True, "4"):
        with pytest.raises(ValueError, match="n_envs: must be an integer >= 1"):
            env.batch(bad)


def test_too_many_robots_in_all_are_refused_naming_both_counts():
    from babyrobot_marl.envs.vector import RaceVectorEnv

    with pytest.raises(ValueError, match=r"n_envs, n_robots: a batch holds at most 1,048,576 robots .* 4,096 x 1,000"):
        RaceVectorEnv(4096, level="maze-64x64", n_robots=1000, start="random", observe="local")


def test_global_observations_past_the_step_limit_are_refused_before_the_race_is_built():
    """64 envs x 3,000 robots of "global" rows: 575 million numbers (4.3 GiB) a step; local views fit."""
    from babyrobot_marl.envs.vector import RaceVectorEnv

    too_many = dict(level="maze-64x64", n_robots=3000, start="random")
    with pytest.raises(ValueError, match=r"one step's observations would be 64 x 3,000 x 8,999 .* observe='local' or 'nearest'"):
        RaceVectorEnv(64, **too_many)
    # refused before the race env builds its 3,000 x 8,999 gather index (216 MB)
    assert peak_bytes(lambda: pytest.raises(ValueError, RaceVectorEnv, 64, **too_many)) < 2**20
    vec = RaceVectorEnv(64, level="maze-64x64", n_robots=3000, start="random", observe="local", view_radius=1)
    assert vec.num_envs == 64 * 3000


def test_a_single_race_with_a_global_view_past_the_step_limit_is_refused_before_its_index_is_built():
    """10,000 robots of "global" rows: 300 million numbers (2.2 GiB) a step, and an index as large."""
    level = "maze-128x128"
    make = partial(race_v0.parallel_env, level=level, n_robots=10_000, start="random")
    message = r"^n_robots: with observe='global' each of 10,000 robots .* 299,990,000 .*observe='local'"
    with pytest.raises(ValueError, match=message):
        make()
    assert peak_bytes(lambda: pytest.raises(ValueError, make)) < 64 * 2**20
    assert make(observe="local").max_num_agents == 10_000


# ------------------------------------------------------------------------ view_radius and k
@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"observe": "local", "view_radius": 7},
         r"^view_radius: must be an integer in 0\.\.6, got 7; a radius of 6 sees the whole 7x7 level"),
        ({"observe": "local", "view_radius": 100_000}, r"^view_radius: must be an integer in 0\.\.6, got 100000"),
        ({"observe": "nearest", "k": 1025}, r"^k: must be an integer in 1\.\.1024, got 1025"),
        ({"observe": "nearest", "k": 10**30}, r"^k: must be an integer in 1\.\.1024, got 1000000000000000000000000000000"),
    ],
)
def test_view_radius_and_k_past_their_bounds_are_refused_by_name_before_anything_is_allocated(kw, message):
    from babyrobot_marl.envs.vector import RaceVectorEnv

    make = partial(race_v0.parallel_env, level="maze-7x7", n_robots=3, start="random", **kw)
    with pytest.raises(ValueError, match=message):
        make()
    assert peak_bytes(lambda: pytest.raises(ValueError, make)) < 2**20
    with pytest.raises(ValueError, match=message):  # the batch engine's vector env takes the same arguments
        RaceVectorEnv(2, level="maze-7x7", n_robots=3, start="random", **kw)


def test_the_largest_view_radius_and_k_work():
    from babyrobot_marl.core.checks import MAX_NEAREST_K

    env = race_v0.parallel_env(level="maze-7x7", n_robots=3, start="random", observe="local", view_radius=6)
    obs, _ = env.reset(seed=0)
    assert obs["robot_0"].shape == (2 + 6 * 13 * 13,)
    small = race_v0.parallel_env(level="race-2", n_robots=2, observe="local", view_radius=2)  # the default fits any level
    assert small.reset(seed=0)[0]["robot_0"].shape == (2 + 6 * 5 * 5,)
    env = race_v0.parallel_env(level="maze-7x7", n_robots=3, start="random", observe="nearest", k=MAX_NEAREST_K)
    obs, _ = env.reset(seed=0)
    assert obs["robot_0"].shape == (2 + 2 * MAX_NEAREST_K,)
    assert (obs["robot_0"][6:] == [13, 13] * (MAX_NEAREST_K - 2)).all()  # missing: [2W - 1, 2H - 1]


def test_local_rows_of_many_robots_past_the_step_limit_are_refused_naming_view_radius():
    make = partial(race_v0.parallel_env, level="maze-256x256", n_robots=200, start="random", observe="local", view_radius=255)
    with pytest.raises(ValueError, match=r"^view_radius, n_robots: 200 robots seeing 1,566,728 numbers each .* 268,435,456"):
        make()
