from torchrl.collectors import SyncDataCollector  # "Collector" from TorchRL 0.12 on
from torchrl.envs import GymEnv, GymWrapper, PettingZooWrapper, check_env_specs

from babyrobot_marl import race_v0
from babyrobot_marl.envs.vector import BabyRobotVectorEnv

env = GymEnv("babyrobot_marl/BabyRobot-v0", level="maze-8x8")
check_env_specs(env)
venv = GymWrapper(BabyRobotVectorEnv(4, level="maze-8x8", autoreset_mode="same-step"))
check_env_specs(venv)
race = PettingZooWrapper(race_v0.parallel_env(level="race-4", n_robots=4, finished="freeze", obs_encoding="onehot"))
check_env_specs(race)
collector = SyncDataCollector(race, policy=None, frames_per_batch=64, total_frames=128)
for batch in collector:
    print(batch["robot", "info", "outcome"].shape)  # numeric infos stack: [64, 4]
collector.shutdown()
