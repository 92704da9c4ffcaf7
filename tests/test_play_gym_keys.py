"""``gymnasium.utils.play.play(env)`` drives BabyRobot-v0 from the keyboard (pygame, SDL's dummy video driver)."""

from __future__ import annotations

import gymnasium
import pytest

import babyrobot_marl  # noqa: F401  (registers the env)
from babyrobot_marl.core.actions import Action
from babyrobot_marl.envs import keys


def test_the_key_map_is_arrows_wasd_and_space_for_stay():
    env = gymnasium.make("babyrobot_marl/BabyRobot-v0")
    mapping = env.unwrapped.get_keys_to_action()
    assert mapping[(ord("w"),)] == Action.NORTH and mapping[(ord("s"),)] == Action.SOUTH
    assert mapping[(ord("d"),)] == Action.EAST and mapping[(ord("a"),)] == Action.WEST
    assert mapping[(ord(" "),)] == Action.STAY
    assert sorted(set(mapping.values())) == [0, 1, 2, 3, 4]
    assert all(isinstance(k, tuple) and all(type(c) is int for c in k) for k in mapping)


@pytest.fixture
def pygame(monkeypatch):
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")  # no display needed
    monkeypatch.setenv("SDL_AUDIODRIVER", "dummy")
    return pytest.importorskip("pygame", reason="pygame is in the 'play' extra: pip install -e '.[play]'")


def test_the_arrow_key_codes_are_pygames(pygame):
    assert (keys.SDL_K_UP, keys.SDL_K_DOWN, keys.SDL_K_LEFT, keys.SDL_K_RIGHT) == (
        pygame.K_UP, pygame.K_DOWN, pygame.K_LEFT, pygame.K_RIGHT,
    )  # fmt: skip


def test_gymnasium_play_drives_the_robot_to_the_exit_with_arrows_and_wasd(pygame, monkeypatch):
    from gymnasium.utils.play import play

    # press and release: right arrow, d, down arrow, s (the default level: start (0, 0), exit (2, 2)), then close
    presses = [pygame.K_RIGHT, pygame.K_d, pygame.K_DOWN, pygame.K_s]
    script = [[]]  # the first frame: reset
    for key in presses:
        script += [[pygame.event.Event(pygame.KEYDOWN, key=key)], [pygame.event.Event(pygame.KEYUP, key=key)]]
    script += [[], [pygame.event.Event(pygame.QUIT)]]
    real_get = pygame.event.get

    def get(*args, **kwargs):  # post this frame's scripted events to the real queue, then read it
        for event in script.pop(0) if script else [pygame.event.Event(pygame.QUIT)]:
            pygame.event.post(event)
        return real_get(*args, **kwargs)

    monkeypatch.setattr(pygame.event, "get", get)
    steps = []
    env = gymnasium.make("babyrobot_marl/BabyRobot-v0", level="default", render_mode="rgb_array")

    def record(obs, next_obs, action, reward, terminated, *_):
        steps.append((action, tuple(next_obs), terminated))

    play(env, fps=1000, wait_on_player=True, seed=0, callback=record)
    assert steps == [
        (Action.EAST, (1, 0), False),
        (Action.EAST, (2, 0), False),
        (Action.SOUTH, (2, 1), False),
        (Action.SOUTH, (2, 2), True),
    ]
