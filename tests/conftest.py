"""Shared test set-up: make the package importable from a source checkout (no install needed), keep
Hypothesis's files out of the checkout (a run leaves nothing behind in the repository), draw plots
headless, and mark the heavy tests that the quick loop ``pytest -q -m "not heavy"`` leaves out."""

from __future__ import annotations

import ast
import contextlib
import functools
import os
import re
import sys
from pathlib import Path

# Plots headless (matplotlib's Agg backend). gymnasium.utils.play asks for TkAgg when imported, which
# fails once pyplot is loaded on a machine without a display, and it then warns "matplotlib is not
# installed": import it first, while pyplot is not loaded (the request only sets a name), then go
# back to Agg.
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
with contextlib.suppress(Exception):  # no pygame (the play extra): the module does not load, and warns nothing
    import gymnasium.utils.play  # noqa: E402, F401
try:
    import matplotlib  # noqa: E402
except ImportError:
    pass
else:
    matplotlib.use("Agg")

import pytest  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
# Test files that start a browser, run notebooks in a kernel, train, soak, fuzz or property-test with
# many random examples, or run every command of the docs: the full suite runs them, the quick loop does
# not (docs blocks that train are marked in tests/test_docs_blocks.py too)
HEAVY_FILES = (
    "test_browser.py", "test_browser_harness.py", "test_browser_play.py", "test_browser_reopen.py", "test_browser_replay.py",
    "test_notebooks.py", "test_reliability_soak.py", "test_ppo.py", "test_family_trainer.py", "test_training_race.py",
    "test_training_single.py", "test_train_cli.py", "test_examples.py", "test_policy_files.py", "test_cli_solve_train.py",
    "test_reliability_properties.py", "test_reliability_levels_fuzz.py", "test_reliability_render.py", "test_cli_fuzz.py",
    "test_docs_blocks.py", "test_clean_runs.py", "test_readme_pictures.py", "test_overlay.py",
    "test_own_goals_trainer.py", "test_recurrent.py",
)
# Tests of the quick files that take seconds each (random crowds beside a reference, frames against
# a fresh renderer, evaluations of saved policies): the full suite runs them, the quick loop does not
HEAVY_TESTS = frozenset({
    "test_imitation.py::test_a_short_imitation_run_saves_and_evaluates_and_races",
    "test_batch.py::test_array_collisions_equal_the_scalar_rules_on_random_crowds",
    "test_batch.py::test_batch_with_own_goals_matches_separate_race_envs_step_by_step",
    "test_bench_pogema_mazes.py::test_a_policy_trained_for_the_exits_is_refused_before_any_episode",
    "test_bench_pogema_mazes.py::test_a_remembering_policy_acts_as_each_robot_bound_to_the_env_would",
    "test_bench_pogema_mazes.py::test_the_table_shows_our_figures_with_intervals_beside_the_published_ones",
    "test_benchmark_floors.py::test_the_batch_benchmark_exits_1_below_make_vecs_25x_floor_and_reports_the_infos_cost",
    "test_canvas.py::test_a_browser_redraw_after_a_replay_shows_the_replayed_scene_not_the_live_one",
    "test_canvas.py::test_a_canvas_without_a_cell_size_fills_90_percent_of_the_column_with_the_pixels_for_it",
    "test_canvas.py::test_a_layer_the_browser_may_show_empty_gets_its_level_as_rectangles",
    "test_canvas.py::test_a_picture_past_the_rectangle_cap_goes_as_png_over_a_coarse_copy_drawn_first",
    "test_canvas.py::test_after_an_episode_the_replay_bar_shows_its_scenes_on_the_same_canvas_without_stepping",
    "test_canvas.py::test_an_env_with_a_canvas_still_pickles_and_the_copy_has_none",
    "test_canvas.py::test_changing_only_the_panel_does_not_resend_the_level",
    "test_canvas.py::test_human_mode_in_jupyter_shows_a_canvas_and_a_still_of_its_frame_at_twice_its_css_size",
    "test_canvas.py::test_race_human_mode_draws_every_robot_with_the_legend_and_snapshots_the_final_ranks",
    "test_canvas.py::test_render_fps_is_the_env_own_and_reaches_the_canvas",
    "test_canvas.py::test_the_bottom_layer_shows_exactly_the_rgb_array_pixels_at_twice_the_cell_size",
    "test_canvas.py::test_the_canvas_legend_stops_growing_past_eight_robots_and_an_oversized_panel_is_refused_before_drawing",
    "test_canvas.py::test_the_level_and_overlay_go_under_the_robots_and_labels_and_panel_over_them",
    "test_canvas.py::test_the_png_is_refreshed_when_an_episode_ends_and_when_the_env_closes",
    "test_canvas.py::test_the_race_legend_changes_with_the_frame_that_shows_the_robots_where_they_end",
    "test_cli.py::test_python_m_play_shortest_on_the_default_level_prints_4_steps_and_return_minus_3",
    "test_cli.py::test_python_m_with_bad_input_prints_one_line_and_no_traceback",
    "test_cli_hostile_input.py::test_a_fifo_as_level_is_refused_without_waiting_for_a_writer",
    "test_collisions_crowds.py::test_crowds_of_tens_of_robots_follow_the_reference_in_both_engines",
    "test_collisions_soft.py::test_crowds_of_hundreds_equal_pogemas_algorithm",
    "test_collisions_soft.py::test_every_engine_equals_pogemas_algorithm_on_random_boards",
    "test_crowd_defaults.py::test_a_crowd_trains_with_the_crowd_defaults_and_says_so",
    "test_crowd_defaults.py::test_evaluate_shows_the_settings_a_policy_was_trained_with",
    "test_crowd_defaults.py::test_given_settings_and_pass_collisions_train_without_the_crowd_defaults",
    "test_ecosystem_suites.py::test_api_test",
    "test_ecosystem_suites.py::test_api_tests_on_the_envs_pettingzoo_make_builds",
    "test_ecosystem_suites.py::test_performance_benchmark",
    "test_ecosystem_suites.py::test_seed_test",
    "test_engine.py::test_uniform_and_uniform_array_are_bit_identical",
    "test_evaluate.py::test_a_maze_family_by_size_is_evaluated_on_unseen_mazes_and_named_as_given",
    "test_evaluate.py::test_a_policy_file_of_format_1_or_2_is_evaluated_as_play_runs_it",
    "test_evaluate.py::test_a_saved_policy_is_evaluated_and_refused_by_name_on_levels_it_cannot_read",
    "test_evaluate.py::test_a_saved_policy_row_is_named_by_its_file",
    "test_evaluate.py::test_a_saved_policy_samples_by_default_seeded_by_seed_and_takes_its_argmax_with_greedy",
    "test_evaluate.py::test_shortest_robots_all_reach_random_ones_are_bounded_and_every_crowd_plays_the_same_episodes",
    "test_evaluate.py::test_the_command_prints_a_table_and_the_json_last_line",
    "test_evaluate.py::test_the_json_rounds_to_four_significant_digits",
    "test_global_observations.py::test_batch_global_rows_equal_each_single_race",
    "test_legend.py::test_a_large_race_legend_is_compact_a_few_lines_of_entries",
    "test_legend.py::test_the_frame_limit_counts_the_legend_and_is_refused_by_cell_size_before_drawing",
    "test_legend.py::test_the_legend_of_a_1200_robot_race_fits_the_frame",
    "test_level.py::test_random_levels_write_the_canonical_text_and_read_back_equal",
    "test_level_families.py::test_evaluation_mazes_are_never_training_mazes_by_content_on_small_families",
    "test_level_families.py::test_the_env_is_sized_for_the_largest_level_and_races_on_each_drawn_size",
    "test_lifelong.py::test_the_batch_engine_plays_lifelong_races_as_the_env_does",
    "test_limits.py::test_a_single_race_with_a_global_view_past_the_step_limit_is_refused_before_its_index_is_built",
    "test_limits.py::test_global_observations_past_the_step_limit_are_refused_before_the_race_is_built",
    "test_limits.py::test_local_rows_of_many_robots_past_the_step_limit_are_refused_naming_view_radius",
    "test_limits.py::test_the_core_dense_arrays_past_the_limit_are_refused_before_allocating",
    "test_limits.py::test_the_dense_model_past_its_limit_names_the_limit_and_the_sparse_alternative",
    "test_limits.py::test_the_largest_maze_is_within_the_level_size_limit",
    "test_limits.py::test_the_longest_level_text_with_crlf_line_ends_and_an_indent_is_within_the_character_limit",
    "test_observe.py::test_local_rows_read_the_level_and_the_robots_cell_by_cell",
    "test_observe.py::test_nearest_rows_list_the_k_nearest_racing_robots_ties_to_the_lower_number",
    "test_picture.py::test_every_text_stays_inside_its_cell_at_every_cell_size",
    "test_planning.py::test_simulator_step_frequencies_match_the_model",
    "test_planning.py::test_the_frequency_check_catches_a_model_off_by_a_tenth",
    "test_play_keys.py::test_the_notebook_module_imports_no_widget_library_until_it_is_used",
    "test_play_notebook.py::test_in_a_race_tab_switches_the_robot_you_drive_and_the_others_follow_their_policy",
    "test_play_notebook.py::test_the_editor_builds_a_level_from_clicks_and_plays_it",
    "test_play_notebook.py::test_the_editor_sends_a_new_canvas_its_picture_as_rectangles_and_edits_as_png",
    "test_play_notebook.py::test_the_editor_starts_from_a_level_and_counts_race_starts",
    "test_play_notebook.py::test_the_player_panel_says_where_the_robots_are_in_words_and_frames_the_driven_robot",
    "test_play_notebook.py::test_the_player_takes_an_env_made_by_gymnasium_or_pettingzoo",
    "test_play_notebook.py::test_the_player_under_the_editor_follows_every_edit",
    "test_play_terminal.py::test_race_human_must_name_a_robot_of_the_race",
    "test_play_terminal.py::test_sigterm_and_hangup_restore_the_terminal",
    "test_play_terminal.py::test_wasd_bump_restart_and_a_second_episode",
    "test_play_terminal.py::test_without_a_terminal_it_says_so_and_exits_2",
    "test_race_rules.py::test_resolve_collisions_agrees_with_a_brute_force_reading_of_the_rules",
    "test_race_rules.py::test_resolve_collisions_does_not_depend_on_the_order_of_the_robots",
    "test_reliability_determinism.py::test_a_copy_taken_before_the_first_reset_behaves_like_a_fresh_env",
    "test_reliability_determinism.py::test_same_seed_gives_the_same_trajectories_in_fresh_processes_whatever_the_hash_seed",
    "test_render_crowd.py::test_only_a_frames_clashing_cells_are_drawn_the_general_way",
    "test_render_crowd.py::test_the_fast_path_gives_the_general_paths_pixels_on_random_crowds",
    "test_render_memory.py::test_a_crowd_s_frame_is_drawn_again_from_the_caches_without_rasterising",
    "test_render_rgb.py::test_a_cell_block_is_keyed_by_all_its_robots_and_the_burst_by_its_cells",
    "test_render_rgb.py::test_a_race_legend_stops_growing_past_eight_robots_and_the_frame_limit_counts_it",
    "test_render_rgb.py::test_kept_blocks_and_legend_pieces_equal_a_fresh_renderers_frames",
    "test_render_rgb.py::test_the_kept_frame_redraws_changed_legend_rows_and_a_new_overlay",
    "test_train_limits.py::test_a_maze_too_large_to_stack_by_the_hundred_trains_evaluates_and_saves",
    "test_train_limits.py::test_an_atlas_holds_as_many_mazes_as_the_level_limit_allows",
    "test_train_limits.py::test_the_command_the_gif_refusal_recommends_runs",
    "test_train_limits.py::test_the_policy_is_saved_before_the_final_evaluation_which_may_still_fail",
    "test_video.py::test_a_gif_shows_in_nbconvert_html_not_as_its_python_repr",
    "test_video.py::test_episode_frames_of_a_race_end_when_every_robot_has_finished",
    "test_window_policy.py::test_play_runs_a_family_policy_on_one_robots_window",
    "test_window_policy.py::test_race_shows_a_family_policy_its_own_observations",
    "test_window_policy.py::test_the_action_cache_stays_bounded_over_a_long_evaluation",
    "test_workers.py::test_a_spawn_worker_that_only_knows_the_id_string_makes_and_steps_the_env",
    "test_workers.py::test_async_vector_env_with_spawn_workers_from_the_module_id",
})
HEAVY_NAMES = ("learns",)  # a test that trains in a file of quick ones: its name says it learns
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

# the real-browser tests' fixtures: one JupyterLab and one Chromium for the session
from tests.browser.fixtures import browser_log, browser_ready, lab, page, screenshots  # noqa: E402, F401

try:
    from hypothesis import settings
except ImportError:  # the test extra is not installed: the property tests skip or fail on their own
    settings = None
else:
    # No example database (it would be ./.hypothesis/examples) and no deadline: a loaded machine
    # runs an example slower, and a property test checks the property, not the speed.
    settings.register_profile("babyrobot_marl", database=None, deadline=None)
    settings.load_profile("babyrobot_marl")


@pytest.hookimpl(trylast=True)  # after pytest's tmp_path plugin has set up its factory
def pytest_configure(config: pytest.Config) -> None:
    """Hypothesis still caches the constants it reads from the source (``.hypothesis/constants``
    under the working directory, written while the tests are collected): under pytest's temporary
    folder instead."""
    if settings is not None:
        from hypothesis import configuration

        configuration.set_hypothesis_home_dir(config._tmp_path_factory.mktemp("hypothesis"))


# How a test file skips when the train extra is missing: a module-level importorskip skips every test
# of the file; one inside a function (a test, a fixture or a helper it calls) skips the tests that use
# it. Those tests are marked ``train``: ``pytest -q -m train`` runs them where the extra is installed.
TRAIN_SIGNS = ('importorskip("torch"', 'importorskip("stable_baselines3', 'importorskip("supersuit"')
# what the skip reason of a test that wants the train extra speaks of
TRAIN_WORDS = re.compile(r"train extra|\btorch\b|stable.baselines3|supersuit", re.I)  # not torchrl: another library


@functools.cache
def _train_names(path: Path) -> frozenset[str] | None:
    """The names of the file's functions that need the train extra (directly or through another of
    its functions), or None when the whole file does."""
    text = path.read_text(encoding="utf-8")
    if not any(sign in text for sign in TRAIN_SIGNS):
        return frozenset()
    tree, lines = ast.parse(text), text.splitlines()

    def signed(node: ast.AST) -> bool:  # the node's own lines (ast.get_source_segment re-reads the whole text)
        return any(sign in line for line in lines[node.lineno - 1 : node.end_lineno] for sign in TRAIN_SIGNS)

    functions: dict[str, ast.AST] = {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            functions[node.name] = node
        elif signed(node):
            return None  # a module-level skip
    needs = {name for name, node in functions.items() if signed(node)}
    calls = {name: {n.id for n in ast.walk(node) if isinstance(n, ast.Name)} for name, node in functions.items()}
    grown = True
    while grown:  # a function that calls (or takes as a fixture) one that needs the extra needs it too
        more = {name for name, names in calls.items() if names & needs or _arguments(functions[name]) & needs}
        grown = not more <= needs
        needs |= more
    return frozenset(needs)


def _arguments(node: ast.AST) -> set[str]:
    return {a.arg for a in node.args.args} if isinstance(node, ast.FunctionDef) else set()


def _needs_train(item: pytest.Item) -> bool:
    names = _train_names(item.path)
    if names is None:
        return True
    owner = item.cls.__name__ if getattr(item, "cls", None) is not None else getattr(item, "originalname", item.name)
    return owner in names or bool(set(getattr(item, "fixturenames", ())) & names)


# What a test file that exercises Gymnasium's or PettingZoo's API names: the libraries themselves, their
# env checkers, gymnasium.make and vector envs. Those files are marked ``gymnasium`` and CI runs them
# (``pytest -m "gymnasium and not heavy"``) again on gymnasium 1.2.2, the version ray[rllib] pins.
GYMNASIUM_SIGNS = re.compile(r"\bgymnasium\b|\bpettingzoo\b|\bcheck_env\b|\bgym\.make\b|\bmake_vec\b|VectorEnv\b")


@functools.cache
def uses_gymnasium(path: Path) -> bool:
    """Whether the test file names Gymnasium's or PettingZoo's API anywhere (its imports, its tests
    or its helpers)."""
    return GYMNASIUM_SIGNS.search(path.read_text(encoding="utf-8")) is not None


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """``heavy``: the browser, notebook, training and soak tests (``slow`` ones included); ``train``:
    the tests of files that skip without the train extra; ``gymnasium``: the tests of files that use
    Gymnasium's or PettingZoo's API."""
    for item in items:
        test_id = f"{item.path.name}::{getattr(item, 'originalname', item.name)}"
        if (item.path.name in HEAVY_FILES or test_id in HEAVY_TESTS or item.get_closest_marker("slow")
                or any(n in item.name for n in HEAVY_NAMES)):
            item.add_marker(pytest.mark.heavy)
        if _needs_train(item):
            item.add_marker(pytest.mark.train)
        if uses_gymnasium(item.path):
            item.add_marker(pytest.mark.gymnasium)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo) -> pytest.TestReport:
    """A test that skips for want of the train extra but is not marked ``train`` fails: the run with
    the train extra (``-m train``) would never run it."""
    report = yield
    if report.skipped and item.get_closest_marker("train") is None:
        reason = str(report.longrepr[-1]) if isinstance(report.longrepr, tuple) else str(report.longrepr)
        if TRAIN_WORDS.search(reason):
            report.outcome = "failed"
            report.longrepr = f"skipped ({reason}) but not marked train: mark it, or 'pytest -m train' never runs it"
    return report
