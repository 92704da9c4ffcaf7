from benchmarl.algorithms import MappoConfig
from benchmarl.environments.pettingzoo.common import PettingZooClass
from benchmarl.experiment import Experiment, ExperimentConfig
from benchmarl.models.mlp import MlpConfig
from torchrl.envs import PettingZooWrapper

from babyrobot_marl import race_v0


class RaceTask(PettingZooClass):
    """The race as a BenchMARL task: PettingZoo's parallel API through TorchRL, one-hot observations."""

    def get_env_fun(self, num_envs, continuous_actions, seed, device):
        return lambda: PettingZooWrapper(
            race_v0.parallel_env(**self.config), categorical_actions=True, device=device, seed=seed, return_state=True
        )

    def supports_continuous_actions(self):
        return False

    def supports_discrete_actions(self):
        return True

    def has_state(self):
        return True

    @staticmethod
    def env_name():
        return "babyrobot_race"


task = RaceTask(
    name="RACE_4", config=dict(level="race-4", n_robots=4, finished="freeze", max_cycles=40, obs_encoding="onehot")
)
config = ExperimentConfig.get_from_yaml()
config.max_n_iters, config.loggers, config.evaluation, config.create_json = 2, [], False, False
config.on_policy_collected_frames_per_batch, config.on_policy_n_envs_per_worker = 200, 2
config.on_policy_minibatch_size, config.on_policy_n_minibatch_iters = 100, 1
config.checkpoint_at_end, config.render = False, False
experiment = Experiment(
    task=task, algorithm_config=MappoConfig.get_from_yaml(), model_config=MlpConfig.get_from_yaml(),
    critic_model_config=MlpConfig.get_from_yaml(), seed=0, config=config,
)
experiment.run()
print(experiment.n_iters_performed)
