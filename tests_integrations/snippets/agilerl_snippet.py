from agilerl.algorithms import IPPO
from agilerl.training.train_multi_agent_on_policy import train_multi_agent_on_policy
from agilerl.vector.pz_async_vec_env import AsyncPettingZooVecEnv

from babyrobot_marl import race_v0

kwargs = dict(level="race-4", n_robots=4, finished="freeze", max_cycles=30, obs_encoding="onehot")
env = AsyncPettingZooVecEnv([lambda: race_v0.parallel_env(**kwargs) for _ in range(2)])
env.reset(seed=0)
agent = IPPO(
    observation_spaces=[env.single_observation_space(a) for a in env.possible_agents],
    action_spaces=[env.single_action_space(a) for a in env.possible_agents],
    agent_ids=env.possible_agents, learn_step=64, batch_size=32,
)
pop, fitnesses = train_multi_agent_on_policy(env, "race", "IPPO", [agent], max_steps=256, evo_steps=128, verbose=False)
env.close()
print(fitnesses)
