"""RLlib tests: run only in a venv with the ``rllib`` extra (``bash .ci/rllib.sh``), never with ``tests/``.

Puts the repository root first on ``sys.path`` and gives the tests one small local Ray
(two CPUs, no dashboard, on the loopback address), shut down when the session ends so no process is left behind.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))


@pytest.fixture(scope="session")
def ray_local():
    import ray

    from babyrobot_marl.integrations.rllib import init_local_ray

    init_local_ray(2, log_to_driver=False, configure_logging=False)
    yield ray
    ray.shutdown()
