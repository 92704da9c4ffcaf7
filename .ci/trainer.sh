#!/usr/bin/env bash
# Issue 16 (fast PPO trainer): the training benchmark runs end to end in quick mode, beside SB3
# (tiny budgets: the figures are in README.md). Uses the CI venv that .ci/run made.
set -euo pipefail
cd "$(dirname "$0")/.."
py=${CI_VENV:-.venv-ci-train}/bin/python
"$py" benchmarks/bench_train.py --quick
"$py" benchmarks/bench_families.py --quick  # issue 27: the fast trainer on a level family, judged on unseen mazes (smoke run)
