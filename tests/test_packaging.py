"""Packaging metadata: the licence as an SPDX expression with its file, and the PEP 561 marker shipped."""

from __future__ import annotations

from pathlib import Path

import pytest

tomllib = pytest.importorskip("tomllib", reason="tomllib is in the standard library from Python 3.11")

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_the_licence_is_an_spdx_expression_with_its_licence_file():
    project = PYPROJECT["project"]
    assert project["license"] == "MIT"  # a string (PEP 639), not the table setuptools stops accepting
    assert project["license-files"] == ["LICENSE"]
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License") and "babyrobot_marl developers" in text
    requires = PYPROJECT["build-system"]["requires"]
    assert any(r.replace(" ", "").startswith("setuptools>=") and int(r.split(">=")[1].split(".")[0]) >= 77 for r in requires)


def test_the_type_marker_is_in_the_package_and_shipped():
    assert (ROOT / "babyrobot_marl" / "py.typed").is_file()
    assert "py.typed" in PYPROJECT["tool"]["setuptools"]["package-data"]["babyrobot_marl"]


def test_the_test_extra_needs_no_torch_and_the_train_extra_brings_the_trainers():
    extras = PYPROJECT["project"]["optional-dependencies"]
    names = {r.split(">")[0].split("=")[0].split("[")[0].strip().lower() for r in extras["test"]}
    assert not names & {"torch", "stable-baselines3", "supersuit"}, names
    train = " ".join(extras["train"]).lower()
    assert "stable-baselines3" in train and "supersuit" in train
