import ray
from ray.rllib.algorithms.ppo import PPOConfig
from ray.rllib.env.wrappers.pettingzoo_env import ParallelPettingZooEnv
from ray.tune.registry import register_env

from babyrobot_marl import race_v0
from babyrobot_marl.integrations.rllib import init_local_ray

# RLlib's own PettingZoo wrapper and default encoder: one-hot Box observations need no connector
register_env("race", lambda cfg: ParallelPettingZooEnv(race_v0.parallel_env(**cfg)))
race = dict(level="race-4", n_robots=4, finished="freeze", max_cycles=40, obs_encoding="onehot")
config = (
    PPOConfig()
    .environment("race", env_config=race)
    .env_runners(num_env_runners=0)
    .multi_agent(policies={"shared"}, policy_mapping_fn=lambda agent_id, episode, **kwargs: "shared")
    .training(train_batch_size_per_learner=400, minibatch_size=100, num_epochs=1)
)
init_local_ray(num_cpus=1)  # Ray on 127.0.0.1 only, no dashboard
algo = config.build_algo()
print(algo.train()["env_runners"]["agent_episode_returns_mean"])
algo.stop()
ray.shutdown()
