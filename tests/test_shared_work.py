"""Shared work: compiled levels cached (bounded) and shared by envs; one shortest-path search per table."""

from __future__ import annotations

from babyrobot_marl import BabyRobotEnv, Rules, compile_level, levels, policies, race_v0
from babyrobot_marl.core import table as table_module
from babyrobot_marl.policies.shortest import shortest_path_actions


def test_envs_on_one_level_and_rules_share_one_compiled_table():
    a = race_v0.parallel_env(level="maze-16x16", n_robots=3, start="random")
    b = race_v0.parallel_env(level="maze-16x16", n_robots=5, start="random", collisions="block")
    single = BabyRobotEnv(level="maze-16x16")
    assert a.table is b.table is single.table
    assert a.table.lists is b.table.lists  # derived tables are shared too
    other_rules = race_v0.parallel_env(level="maze-16x16", n_robots=3, start="random", collisions="bounce")
    assert other_rules.table is not a.table and other_rules.table.rules.collisions == "bounce"


def test_the_cache_is_bounded_and_keeps_equal_levels_apart_by_name():
    compile_level.cache_clear()
    level = levels.get("maze-8x8")
    first = compile_level(level)
    for seed in range(table_module.COMPILED_CACHE + 2):  # push it out
        compile_level(levels.get(f"maze-5x5-s{seed}"))
    assert compile_level.cache_info().currsize == table_module.COMPILED_CACHE
    again = compile_level(level)
    assert again is not first and again.level == first.level  # compiled afresh, the same tables
    assert (again.target == first.target).all()
    renamed = type(level).from_ascii(level.to_ascii(), name="another name")
    assert compile_level(renamed).level.name == "another name"
    assert compile_level(level, Rules(glass_pass_prob=1.0)) is not compile_level(level)


def test_shortest_path_robots_on_one_table_share_one_search():
    t = compile_level(levels.get("mixed-8x8"))
    robots = [policies.make("shortest", t) for _ in range(50)]
    assert all(r.actions is robots[0].actions and r._by_cell is robots[0]._by_cell for r in robots)
    assert (robots[0].actions == shortest_path_actions(t)).all()
    assert not robots[0].actions.flags.writeable


def test_a_table_lists_its_free_cells_once_as_the_level_does():
    t = compile_level(levels.get("mixed-8x8"))
    assert t.free_cells == tuple(t.cell_id(c) for c in t.level.free_cells())
    assert t.free_cells is t.free_cells
