import gymnasium as gym
import tianshou as ts
from tianshou.algorithm import DQN
from tianshou.algorithm.modelfree.dqn import DiscreteQLearningPolicy
from tianshou.algorithm.optim import AdamOptimizerFactory
from tianshou.trainer import OffPolicyTrainerParams
from tianshou.utils.net.common import Net

import babyrobot_marl  # noqa: F401  (registers babyrobot_marl/BabyRobot-v0)


def make():
    return gym.make("babyrobot_marl/BabyRobot-v0", level="default", obs_encoding="onehot", max_steps=30)

env = make()
train_envs, test_envs = ts.env.DummyVectorEnv([make] * 2), ts.env.DummyVectorEnv([make] * 2)
net = Net(state_shape=env.observation_space.shape, action_shape=env.action_space.n, hidden_sizes=[32])
policy = DiscreteQLearningPolicy(model=net, action_space=env.action_space, eps_training=0.2)
algorithm = DQN(policy=policy, optim=AdamOptimizerFactory(lr=1e-3), target_update_freq=20)
buffer = ts.data.VectorReplayBuffer(2000, len(train_envs))
train_collector = ts.data.Collector(algorithm, train_envs, buffer, exploration_noise=True)
test_collector = ts.data.Collector(algorithm, test_envs)
result = algorithm.run_training(
    OffPolicyTrainerParams(
        training_collector=train_collector, test_collector=test_collector, max_epochs=2, epoch_num_steps=200,
        collection_step_num_env_steps=10, batch_size=32, test_step_num_episodes=2, show_progress=False,
    )
)
print(result.best_reward)
