#!/usr/bin/env bash
# CI for the AgileRL integration in its own venv: AgileRL 2.58 pins pettingzoo < 1.27 and tensordict 0.13
# (TorchRL's venv in .ci/integrations.sh needs another) and imports peft at start-up. Torch's CPU build first.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS

adir=.venv-ci-agilerl
.ci/venv "$adir" torch
.ci/locked "$adir/bin/pip" install -q "agilerl==2.58.0" peft pytest -e .
"$adir/bin/python" -c "import torch, agilerl; assert '+cpu' in torch.__version__, torch.__version__"  # agilerl kept the CPU build
"$adir/bin/python" -m pytest -q -p no:cacheprovider tests_integrations/test_agilerl.py
echo "agilerl: $((SECONDS - start)) s in all"
