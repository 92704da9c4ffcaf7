"""The ``train`` mark that CI's training lane selects (``pytest -m train``): which tests of a file
need the train extra, read from how the file skips without it."""

from __future__ import annotations

from tests.conftest import TRAIN_WORDS, _train_names


def test_a_module_level_skip_marks_every_test_of_the_file(tmp_path):
    path = tmp_path / "test_a.py"
    path.write_text('import pytest\ntorch = pytest.importorskip("torch")\n\ndef test_x():\n    pass\n')
    assert _train_names(path) is None


def test_a_skip_inside_a_helper_marks_the_tests_and_fixtures_that_use_it(tmp_path):
    path = tmp_path / "test_b.py"
    path.write_text(
        "import pytest\n\n"
        'def sb3():\n    return pytest.importorskip("stable_baselines3")\n\n'
        "@pytest.fixture\ndef model():\n    return sb3().PPO\n\n"
        "def test_uses_fixture(model):\n    pass\n\n"
        "def test_calls_helper():\n    sb3()\n\n"
        "def test_plain():\n    pass\n"
    )
    assert _train_names(path) == {"sb3", "model", "test_uses_fixture", "test_calls_helper"}


def test_a_file_without_a_skip_has_no_train_tests(tmp_path):
    path = tmp_path / "test_c.py"
    path.write_text('import pytest\n\ndef test_x():\n    pytest.importorskip("torchrl")\n')
    assert _train_names(path) == frozenset()


def test_skip_reasons_of_the_train_extra_are_told_from_other_libraries():
    assert TRAIN_WORDS.search("could not import 'torch': No module named 'torch'")
    assert TRAIN_WORDS.search("needs the train extra (Stable-Baselines3)")
    assert not TRAIN_WORDS.search("needs torchrl (not installed)")


def test_every_test_named_heavy_by_id_exists():
    from tests.conftest import HEAVY_TESTS, ROOT

    for test_id in HEAVY_TESTS:
        file, function = test_id.split("::")
        text = (ROOT / "tests" / file).read_text(encoding="utf-8")
        assert f"def {function}(" in text, f"{test_id}: no such test (renamed? then rename it in HEAVY_TESTS)"


def test_a_file_naming_gymnasium_or_pettingzoo_api_is_marked_gymnasium(tmp_path):
    from tests.conftest import uses_gymnasium

    for n, body in enumerate(("import gymnasium\n", "from pettingzoo.test import parallel_api_test\n",
                              "env = gym.make('x')\n", "from x import check_env\n", "v = make_vec(1)\n",
                              "class A(SyncVectorEnv):\n    pass\n")):  # fmt: skip
        path = tmp_path / f"test_g{n}.py"
        path.write_text(body)
        assert uses_gymnasium(path), body
    plain = tmp_path / "test_plain.py"
    plain.write_text("import numpy\n\ndef test_x():\n    pass\n")
    assert not uses_gymnasium(plain)


def test_the_gymnasium_files_include_the_envs_checkers_and_adapters():
    """The files CI runs again on gymnasium 1.2.2: every test file that names the libraries' API (the
    single-robot env, the race's Gymnasium and PettingZoo faces, the checkers, the vector envs)."""
    from tests.conftest import ROOT, uses_gymnasium

    marked = {p.name for p in (ROOT / "tests").glob("test_*.py") if uses_gymnasium(p)}
    assert {"test_single_env.py", "test_race_env.py", "test_race_gym.py", "test_race_pettingzoo.py", "test_vector.py",
            "test_ecosystem_suites.py", "test_env_plugins.py", "test_workers.py", "test_time_aware.py"} <= marked
    assert "test_rules.py" not in marked  # the rules alone: no Gymnasium in them
