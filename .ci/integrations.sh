#!/usr/bin/env bash
# CI for the RL library integrations (issue 14), in two venvs of their own, torch's CPU build first in each:
# - .venv-ci-integrations: TorchRL 0.11.1 + BenchMARL 1.5.2 (its pin), Tianshou 2.0.1, SuperSuit, SB3.
#   BenchMARL requires torchvision, which would pull torch 2.14.1 with CUDA: it imports none of it, so it
#   is installed with --no-deps after its real requirements (torchrl, tensordict, hydra-core, tqdm, av).
# - AgileRL runs in .ci/agilerl.sh's venv (it pins pettingzoo < 1.27 and tensordict 0.13).
# - RLlib runs in .ci/rllib.sh's venv (ray[rllib] pins gymnasium 1.2.2).
# - .venv-ci-pogema: POGEMA 1.4 alone (it pins gymnasium 0.28.1), stepped beside the race for collisions="soft";
#   pogema-toolbox's maze generator added to check the maze benchmark's shipped data.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS

dir=.venv-ci-integrations
.ci/venv "$dir" torch
.ci/locked "$dir/bin/pip" install -q "torchrl==0.11.1" "tensordict>=0.11,<0.12" hydra-core tqdm "av<14" "tianshou==2.0.1" pytest -e ".[train]"
.ci/locked "$dir/bin/pip" install -q --no-deps "benchmarl==1.5.2"
"$dir/bin/python" -c "import torch, torchrl, benchmarl, tianshou; assert '+cpu' in torch.__version__, torch.__version__"
echo "integrations venv ready after $((SECONDS - start)) s"
"$dir/bin/python" -m pytest -q -p no:cacheprovider tests_integrations/test_libraries.py

# POGEMA 1.4 (pins gymnasium 0.28.1) in a venv of its own, no torch: the soft-collision test runs in the
# integrations venv and drives POGEMA in a subprocess of this one (tests_integrations/pogema/driver.py)
pdir=.venv-ci-pogema
.ci/venv "$pdir"
.ci/locked "$pdir/bin/pip" install -q "pogema==1.4.*"
POGEMA_PYTHON="$PWD/$pdir/bin/python" "$dir/bin/python" -m pytest -q -p no:cacheprovider tests_integrations/test_pogema_soft.py
"$dir/bin/python" benchmarks/bench_pogema.py --quick --pogema-python "$pdir/bin/python"  # the race beside POGEMA: smoke run
# POGEMA's maze benchmark: the shipped mazes, starts and goals made again by pogema-toolbox (its maze generator
# only: --no-deps skips its plotting and logging stack) and POGEMA, compared; a smoke run, its episodes
# stepped in POGEMA too (equal with on_target="nothing"), and PIBT's and LaCAM's crowds beside them
.ci/locked "$pdir/bin/pip" install -q --no-deps "pogema-toolbox==0.1.1" && .ci/locked "$pdir/bin/pip" install -q "pyyaml<=6.0.1"
"$dir/bin/python" benchmarks/bench_pogema_mazes.py --regenerate --quick --in-pogema --pibt --lacam --pogema-python "$pdir/bin/python"

echo "integrations: $((SECONDS - start)) s in all"
