import gymnasium as gym
import numpy as np
import supersuit as ss

import babyrobot_marl  # noqa: F401  (registers babyrobot_marl/BabyRobot-v0)
from babyrobot_marl import race_v0

# SuperSuit's observation wrappers take Box observations: obs_encoding="box" (or "onehot")
env = race_v0.parallel_env(level="race-4", n_robots=4, finished="remove", obs_encoding="box")
env = ss.dtype_v0(env, np.float32)
env = ss.normalize_obs_v0(env, env_min=0.0, env_max=1.0)
env = ss.frame_stack_v1(env, 3)
env = ss.flatten_v0(env)
env = ss.black_death_v3(env)  # finished robots stay, observing zeros
env = ss.agent_indicator_v0(env)
env = ss.pad_observations_v0(env)
obs, infos = env.reset(seed=0)
for _ in range(40):
    obs, rewards, terms, truncs, infos = env.step({a: env.action_space(a).sample() for a in env.agents})
    if not env.agents:
        break
print({a: o.shape for a, o in obs.items()})

single = ss.frame_stack_v1(ss.normalize_obs_v0(gym.make("babyrobot_marl/BabyRobot-v0", obs_encoding="box"), 0.0, 1.0), 4)
print(single.reset(seed=0)[0].shape)  # (8,): four frames of [x, y] scaled to [0, 1]
