import gymnasium as gym
import torch
from torch import nn
from torch.distributions import Categorical

import babyrobot_marl  # noqa: F401  (registers babyrobot_marl/BabyRobot-v0)

# CleanRL's ppo.py, the parts that touch the env: a SyncVectorEnv of gym.make, Box observations
envs = gym.vector.SyncVectorEnv(
    [lambda: gym.wrappers.RecordEpisodeStatistics(gym.make("babyrobot_marl/BabyRobot-v0", obs_encoding="onehot"))] * 4
)
actor = nn.Sequential(nn.Linear(envs.single_observation_space.shape[0], 64), nn.Tanh(), nn.Linear(64, 5))
obs, _ = envs.reset(seed=1)
for _ in range(200):
    with torch.no_grad():
        action = Categorical(logits=actor(torch.as_tensor(obs))).sample()
    obs, reward, terminations, truncations, infos = envs.step(action.numpy())
    if "episode" in infos:
        print(infos["episode"]["r"][infos["_episode"]])
envs.close()
