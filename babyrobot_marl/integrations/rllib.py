"""The race on Ray RLlib (new API stack): a native ``MultiAgentEnv``, its registration, PPO set-ups.

    from babyrobot_marl.integrations.rllib import shared_policy_config

    config = shared_policy_config({"level": "race-4", "n_robots": 4}, num_env_runners=2, seed=0)
    algo = config.build_algo()
    print(algo.train()["env_runners"]["agent_episode_returns_mean"])

Needs the ``rllib`` extra (``pip install torch==2.13.0 && pip install -e ".[rllib]"``). Nothing
else in ``babyrobot_marl`` imports this module or Ray.

Why a native ``MultiAgentEnv`` and not ``ParallelPettingZooEnv`` over ``race_v0.parallel_env``:
RLlib's wrapper sets ``__all__`` to "every reported agent terminated" / "every reported agent
truncated", so the step that ends a race with one robot finishing and another truncated at
``max_cycles`` ends the episode in neither dict; its ``agents`` list also never shrinks. The
native env reports ``__all__`` from the race itself and keeps ``agents`` current. Speed does
not decide it: in ``benchmarks/bench_rllib.py`` both step at the same rate (within a few per
cent, ~87k env-steps/s for 4 robots), far above what RLlib's sampling loop asks of them.

Seeding: RLlib seeds env runner ``k``'s sub-env ``i`` with ``seed + k + i`` on its first reset
only (``config.debugging(seed=...)``), so runner ``k`` sub-env ``1`` and runner ``k + 1`` sub-env
``0`` would play the same races. The env therefore draws its generator from
``SeedSequence([seed, worker_index])``: every (runner, sub-env) pair plays its own races, and the
same seed gives the same run. Without a seed every env draws fresh entropy.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

try:
    import gymnasium as gym
    from ray.rllib.env.multi_agent_env import MultiAgentEnv
except ImportError as e:  # pragma: no cover - depends on the install
    raise ImportError(
        "babyrobot_marl.integrations.rllib needs Ray RLlib: pip install torch==2.13.0 && pip install -e '.[rllib]'"
    ) from e

from ..core.checks import check_int, shown
from ..envs.race import RaceEnv

ENV_NAME = "babyrobot_marl_race"
SHARED_POLICY = "shared"
LOOPBACK = "127.0.0.1"

__all__ = [
    "ENV_NAME",
    "SHARED_POLICY",
    "RaceMultiAgentEnv",
    "greedy_policy",
    "init_local_ray",
    "per_robot_config",
    "race_config",
    "register_race",
    "shared_policy_config",
    "win_rate",
]


class RaceMultiAgentEnv(MultiAgentEnv):
    """``babyrobot_marl.race_v0`` as an RLlib ``MultiAgentEnv`` (robots act simultaneously).

    ``config`` holds the keyword arguments of ``race_v0.parallel_env`` (``level``, ``n_robots``,
    ``collisions``, ``max_cycles``, ``start``, rules ...); RLlib passes an ``EnvContext``, whose
    ``worker_index`` enters the seed (see the module docstring).

    * Agents ``robot_0`` ... ``robot_{n-1}``, ``Discrete(5)`` actions, the race's ``MultiDiscrete``
      observations (put ``FlattenObservations`` in front of the model, as the configs here do).
    * A robot that reaches the exit is terminated; that step's dicts are its last (RLlib's
      convention for agents that are done). ``agents`` lists the robots of the latest dicts (as
      RLlib's env check expects), so a finished robot leaves it one step later.
    * ``terminateds["__all__"]`` is True when every robot has finished; ``truncateds["__all__"]``
      when the race is cut at ``max_cycles`` (the robots still racing are truncated, those that
      finish in that same step terminated).
    """

    def __init__(self, config: Mapping[str, Any] | None = None):
        super().__init__()
        if config is not None and not isinstance(config, Mapping):
            raise TypeError(f"config: expected a dict of race_v0.parallel_env arguments, got {type(config).__name__}")
        kwargs = dict(config or {})
        finished = kwargs.pop("finished", "remove")
        if finished != "remove":
            raise ValueError(
                f"finished: RLlib takes robots leaving the race as they finish, so only 'remove' is allowed, got {finished!r}"
            )
        self.worker_index = int(getattr(config, "worker_index", 0))
        self.race = RaceEnv(finished="remove", **kwargs)
        self.render_mode = self.race.render_mode
        self.metadata = self.race.metadata
        self.possible_agents = list(self.race.possible_agents)
        self.agents = []
        self.observation_spaces = {a: self.race.observation_space(a) for a in self.possible_agents}
        self.action_spaces = {a: self.race.action_space(a) for a in self.possible_agents}
        self.observation_space = gym.spaces.Dict(self.observation_spaces)
        self.action_space = gym.spaces.Dict(self.action_spaces)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if seed is not None:
            seed = check_int(seed, "seed", lo=0)
            # one stream per (seed, env runner): RLlib's seed + runner + sub-env sums overlap
            seed = int(np.random.SeedSequence([int(seed), self.worker_index]).generate_state(1, np.uint64)[0])
        obs, infos = self.race.reset(seed=seed, options=options)
        self.agents = list(self.race.agents)
        return obs, infos

    def step(self, action_dict: Mapping[str, Any]):
        obs, rewards, terms, truncs, infos = self.race.step(action_dict)
        self.agents = list(obs)  # RLlib's env check wants every agent of this step's dicts in `agents`
        over = not self.race.agents
        cut = over and True in truncs.values()
        terms["__all__"] = over and not cut
        truncs["__all__"] = cut
        return obs, rewards, terms, truncs, infos

    def render(self) -> str | np.ndarray | None:
        return self.race.render()

    def close(self) -> None:
        self.race.close()


def init_local_ray(num_cpus: int | None = None, **kwargs: Any) -> None:
    """Start Ray on this machine alone: its processes listen on the loopback address (127.0.0.1),
    not on the machine's network address, and no dashboard is started; a run on one machine has
    no reason to be reachable from the network (older Ray versions ask no token). ``kwargs``
    go to ``ray.init`` as they are. To join a cluster, call ``ray.init(address=...)`` instead."""
    import ray
    from ray._private import ray_constants

    kwargs.setdefault("include_dashboard", False)
    # Ray 2.x on Linux turns a loopback node address into the machine's network address unless its
    # cluster mode is off (as on macOS and Windows): off while the node starts, so its address is
    # 127.0.0.1, which its servers then bind to. Older versions take the address as it is.
    cluster = getattr(ray_constants, "ENABLE_RAY_CLUSTER", None)
    ray_constants.ENABLE_RAY_CLUSTER = False
    try:
        ray.init(num_cpus=num_cpus, _node_ip_address=LOOPBACK, **kwargs)
    finally:
        if cluster is None:
            del ray_constants.ENABLE_RAY_CLUSTER
        else:
            ray_constants.ENABLE_RAY_CLUSTER = cluster


def make_env(config: Mapping[str, Any] | None = None) -> RaceMultiAgentEnv:
    """The env creator registered with Ray: ``config`` is the algorithm's ``env_config``."""
    return RaceMultiAgentEnv(config)


def register_race(name: str = ENV_NAME) -> str:
    """Register the race with Ray's env registry under ``name``; returns the name for ``config.environment``."""
    from ray.tune.registry import register_env

    if not isinstance(name, str) or not name:
        raise ValueError(f"name: expected a non-empty string, got {name!r}")
    register_env(name, make_env)
    return name


def _to_shared_policy(agent_id: str, episode: Any = None, **kwargs: Any) -> str:
    return SHARED_POLICY


def _to_own_policy(agent_id: str, episode: Any = None, **kwargs: Any) -> str:
    return agent_id


def _flatten_observations(env: Any = None, spaces: Any = None, device: Any = None):
    from ray.rllib.connectors.env_to_module import FlattenObservations

    return FlattenObservations(multi_agent=True)


def race_config(
    env_config: Mapping[str, Any] | None = None,
    *,
    shared: bool = True,
    num_env_runners: int = 0,
    seed: int | None = None,
    hiddens: tuple[int, ...] = (64, 64),
    base: Any = None,
):
    """An ``AlgorithmConfig`` for the race, ready for ``build_algo()``: ``base`` (default ``PPOConfig()``) set up.

    ``shared=True``: one policy ``"shared"`` for all robots (parameter sharing: each robot sees
    itself first, so one network serves all). ``shared=False``: one policy per robot, named
    like the robot (``policy_mapping_fn`` maps ``robot_i`` to ``robot_i``).
    ``num_env_runners=0`` samples in the driver; ``n > 0`` starts ``n`` remote env runners
    (one CPU each). ``seed`` seeds the envs (per runner, see the module docstring) and torch.
    Change anything else on the returned config (``.training(...)``, ``.env_runners(...)``).
    """
    if not isinstance(shared, bool):
        raise TypeError(f"shared: expected True (one shared policy) or False (one per robot), got {shared!r}")
    num_env_runners = check_int(num_env_runners, "num_env_runners", lo=0)
    seed = None if seed is None else check_int(seed, "seed", lo=0)
    if isinstance(hiddens, (str, bytes)) or not isinstance(hiddens, (tuple, list)):
        raise ValueError(f"hiddens: expected a tuple of layer widths such as (64, 64), got {shown(hiddens)}")
    hiddens = tuple(check_int(h, "hiddens", lo=1) for h in hiddens)  # layer widths: counts of units

    from ray.rllib.core.rl_module.default_model_config import DefaultModelConfig
    from ray.rllib.core.rl_module.multi_rl_module import MultiRLModuleSpec
    from ray.rllib.core.rl_module.rl_module import RLModuleSpec

    env_config = dict(env_config or {})
    probe = RaceMultiAgentEnv(env_config)  # bad race arguments fail here, in the driver
    agents = probe.possible_agents
    policies = [SHARED_POLICY] if shared else agents
    mapping: Callable[..., str] = _to_shared_policy if shared else _to_own_policy
    model = DefaultModelConfig(fcnet_hiddens=list(hiddens), vf_share_layers=False)
    if base is None:
        from ray.rllib.algorithms.ppo import PPOConfig

        base = PPOConfig()
    return (
        base.environment(register_race(), env_config=env_config)
        .env_runners(
            num_env_runners=num_env_runners,
            num_envs_per_env_runner=1,
            num_cpus_per_env_runner=1,
            env_to_module_connector=_flatten_observations,
        )
        .multi_agent(policies=set(policies), policy_mapping_fn=mapping)
        .rl_module(rl_module_spec=MultiRLModuleSpec(rl_module_specs={p: RLModuleSpec(model_config=model) for p in policies}))
        .debugging(seed=seed)
    )


def shared_policy_config(env_config: Mapping[str, Any] | None = None, **kwargs: Any):
    """``race_config(env_config, shared=True, ...)``: one policy for all robots."""
    return race_config(env_config, shared=True, **kwargs)


def per_robot_config(env_config: Mapping[str, Any] | None = None, **kwargs: Any):
    """``race_config(env_config, shared=False, ...)``: one policy per robot."""
    return race_config(env_config, shared=False, **kwargs)


def greedy_policy(module: Any, observation_space: gym.Space) -> Callable[[np.ndarray], int]:
    """A scripted-robot-like callable ``obs -> action`` from a trained ``RLModule``.

    It flattens the observation as ``FlattenObservations`` does in training (one-hot per
    ``MultiDiscrete`` entry) and takes the most likely action: what a trained robot does when
    it races the scripted ``shortest`` and ``random`` robots.
    """
    import torch
    from ray.rllib.core.columns import Columns
    from ray.rllib.utils.numpy import flatten_inputs_to_1d_tensor
    from ray.rllib.utils.spaces.space_utils import get_base_struct_from_space

    struct = get_base_struct_from_space(observation_space)

    def act(obs: np.ndarray) -> int:
        flat = flatten_inputs_to_1d_tensor(np.asarray(obs), spaces_struct=struct, batch_axis=False)
        with torch.no_grad():
            out = module.forward_inference({Columns.OBS: torch.as_tensor(flat[None], dtype=torch.float32)})
        return int(torch.argmax(out[Columns.ACTION_DIST_INPUTS][0]))

    return act


def win_rate(
    policy: Callable[[np.ndarray], int],
    env_config: Mapping[str, Any] | None = None,
    opponent: str = "shortest",
    races: int = 100,
    seed: int = 0,
) -> float:
    """Share of ``races`` that ``policy``, driving ``robot_0``, wins against scripted robots.

    Every other robot is the scripted ``opponent`` (``"shortest"`` or ``"random"``, seeded from
    ``seed``). A race is won when ``robot_0`` finishes first; finishing in the same step as the
    first opponent counts as a win too (ranks are shared). Races are seeded ``seed``, ``seed + 1``, ...
    """
    from ..policies import POLICY_NAMES, make

    if opponent not in POLICY_NAMES:
        raise ValueError(f"opponent: must be one of {', '.join(map(repr, POLICY_NAMES))}, got {opponent!r}")
    races, seed = check_int(races, "races", lo=1), check_int(seed, "seed", lo=0)
    race = RaceEnv(**{**dict(env_config or {}), "finished": "remove"})
    rng = np.random.default_rng(seed)
    others = {a: make(opponent, race.table, seed=rng) for a in race.possible_agents[1:]}
    wins = 0
    for k in range(races):
        obs, _ = race.reset(seed=seed + k)
        while race.agents:
            actions = {a: (policy(obs[a]) if a == "robot_0" else others[a](obs[a])) for a in race.agents}
            obs, *_ = race.step(actions)
        wins += race.ranks[0] == 1
    return wins / races
