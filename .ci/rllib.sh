#!/usr/bin/env bash
# CI for the Ray RLlib integration, in its own venv: ray[rllib] pins gymnasium 1.2.2, and the
# rest of the suite must not be held back by that pin. Torch's CPU build goes first (it lies
# on local disk); the rllib extra then finds torch satisfied instead of fetching a CUDA build.
set -euo pipefail
cd "$(dirname "$0")/.."

dir=.venv-ci-rllib
.ci/venv "$dir" torch
.ci/locked "$dir/bin/pip" install -q -e ".[rllib,test]"
"$dir/bin/python" -c "import gymnasium, ray; print('ray', ray.__version__, 'gymnasium', gymnasium.__version__)"
# tests_rllib starts one local Ray (2 CPUs) and shuts it down; a few minutes at most
"$dir/bin/python" -m pytest -q -p no:cacheprovider tests_rllib
# the example end to end, as small as it goes: one iteration, one remote env runner
"$dir/bin/python" examples/rllib_race.py --iterations 1 --num-env-runners 1 --quick
"$dir/bin/python" -m pytest -q -p no:cacheprovider tests_integrations/test_rllib.py  # RLlib's own PettingZoo wrapper on the one-hot race
