import pickle

from stable_baselines3 import PPO

import babyrobot_marl

vec = babyrobot_marl.sb3_vec_env(level="race-4", n_envs=2, n_robots=4, obs_encoding="onehot")
model = PPO("MlpPolicy", vec, n_steps=64, batch_size=64, seed=0).learn(256)
vec = pickle.loads(pickle.dumps(vec))  # the VecEnv pickles with the standard pickle
