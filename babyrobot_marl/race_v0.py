"""# Baby Robot race

Several Baby Robots race to the exit of one level, moving at the same time, under collision
rules. Built on the same compiled level and rules as the single-robot env.

| Import             | `from babyrobot_marl import race_v0`                 |
|--------------------|------------------------------------------------------|
| Actions            | Discrete                                             |
| Parallel API       | Yes                                                  |
| Manual control     | No                                                   |
| Agents             | `agents = ["robot_0", ..., "robot_{n-1}"]`           |
| Agents             | `n_robots` (default 2)                               |
| Action shape       | (1,)                                                 |
| Action values      | Discrete(5)                                          |
| Observation shape  | (2 + 3 * (n_robots - 1),) (`observe="global"`)       |
| Observation values | MultiDiscrete([W, H] + [W, H, 2] * (n_robots - 1))   |
| Local view         | `observe="local"`: see Observations                  |
| Nearest robots     | `observe="nearest"`: see Observations                |
| Own goals          | `goals="own"`: see Own goals                         |
| State shape        | (3 * n_robots,)                                      |
| State values       | Box(0, [W-1, H-1, 1] * n_robots), int64              |

## Actions

| value | name  | effect                 |
|-------|-------|------------------------|
| 0     | STAY  | stay in place          |
| 1     | NORTH | move up (`y - 1`)      |
| 2     | EAST  | move right (`x + 1`)   |
| 3     | SOUTH | move down (`y + 1`)    |
| 4     | WEST  | move left (`x - 1`)    |

## Observations

Every robot observes an int64 vector beginning with its own `[x, y]`; `observe=` picks the rest:

| `observe=`               | after `[x, y]`, per robot                      | values (`MultiDiscrete`)                 | a step |
|--------------------------|------------------------------------------------|------------------------------------------|--------|
| `"global"` (default)     | `[x, y, finished]` of each other robot         | `[W, H] + [W, H, 2] * (n_robots - 1)`    | O(n^2) |
| `"local"`, `view_radius` | a (2r+1) x (2r+1) window, 6 numbers per cell   | `[W, H] + [5, 2, 3, 3, 3, 3] * (2r+1)^2` | O(n)   |
| `"nearest"`, `k`         | `[dx + W - 1, dy + H - 1]` of the k nearest    | `[W, H] + [2W, 2H] * k`                  | O(n)   |

`"global"`: the other robots in the order `i+1, i+2, ..., i-1` (mod `n_robots`: the next robot
first). `"local"` (`view_radius=r`, default 2): the window is centred on the robot, rows north
to south, west to east within a row, each cell `[terrain, robot, north, east, south, west]`.
`"nearest"` (`k`, default 4): the other racing robots nearest first.

In a `"local"` window: `terrain` 0 floor, 1 small puddle, 2 large puddle, 3 blocked cell or
outside the grid, 4 exit; `robot` 1 when another racing robot is on the cell; each side 0 open,
1 wall (the grid's border included), 2 glass wall; cells outside the grid are blocked with
walls on all sides. In `"nearest"`, distance is Manhattan (ties to the lower robot number) and
a missing robot (fewer than `k` others racing) is `[2W - 1, 2H - 1]`. Names and codes:
`babyrobot_marl.core.observe` (`TERRAIN`, `EDGE`, `LOCAL_FEATURES`).
`hint=True` (with `observe="local"`): the row ends with the goal hint of the robot's cell, 5
numbers (nvec 2 each), one per action in the order above: 1 if the action is optimal for one
robot alone (`babyrobot_marl.planning.optimal_actions`: value iteration on the level; other
robots ignored), else 0; all 0 on the exit. Planned once per level (each level drawn at reset
too), not per step.
A finished robot's `[x, y]` is the exit it took (own goals: its target); it is off the board (it
blocks nobody, and local windows and nearest lists do not show it).

`state()` is `[x, y, finished]` of every robot in robot order: a global view for critics.

`obs_encoding="box"`: the same numbers as a float32 `Box`; `"onehot"`: a float32 `Box` with one 1
per entry (`babyrobot_marl.encodings`); `state()` and `state_space` follow.

## Rewards

Each racing robot gets the reward of the cell its step ends in (`Rules`: floor -1, small
puddle -2, large puddle -4, exit 0, or the level's custom rewards), plus `win_bonus`
(default +10) for finishing first; robots that finish in the same first step all get it.
Parked finished robots (`finished="freeze"`) get 0.

## Dynamics

Every racing robot's own move is drawn first (skids on puddles, glass walls), from the env's
seeded generator. Then collisions (`collisions=`):

* `"block"` (default): several robots heading for one cell: one, drawn uniformly, gets it,
  the others stay. Two robots may not swap cells. A robot may follow into a cell its
  occupant leaves in the same step, not into one whose occupant stays. Resolved until
  nothing changes.
* `"bounce"`: as block, but all robots heading for one cell stay.
* `"pass"`: robots do not interact and may share cells.
* `"soft"`: POGEMA 1.4's soft rule, step for step: as block, but the lowest-numbered robot
  heading for a cell gets it (no draw).

A robot that reaches an exit is finished (terminated) and leaves the board.

## Own goals

`goals="own"` gives every robot its own target cell, as in POGEMA's multi-robot pathfinding,
instead of the race to the exits (`goals="exit"`, the default). `env.goals` maps each agent to
its target `(x, y)` (None in the race to the exits). A robot finishes when it stands on its own
target (then it leaves or is parked there, as `finished=` says) and gets the exit reward
(`Rules.exit_reward`, 0) for that step; nobody gets `win_bonus`. The level's exits are plain
floor for this race (floor reward, no finishing, terrain 0 in local windows, starts and goals may
lie on them), and so is another robot's target.

At each reset the targets are drawn from the env's seeded generator (same seed, same targets):
distinct free cells (not blocked, no puddle), each reachable from its robot's start by one
robot's moves and not that start. `reset(options={"goals": [(x, y), ...]})` gives them instead,
one per robot, with or without `"starts"`: distinct cells, not blocked, each reachable from its
robot's start and not that start, else a `ValueError` naming `options["goals"]` (random starts
are then drawn off the given targets). `start="random"` draws starts from cells that have
somewhere to go.

Observations end with the target (after the columns above, before the hint):

| `observe=`              | added at the end of each row                               | values           |
|-------------------------|------------------------------------------------------------|------------------|
| `"global"`, `"nearest"` | the target's `[x, y]`                                      | `[W, H]`         |
| `"local"`               | the target channel: (2r+1)^2 numbers, the window's cells   | `[2] * (2r+1)^2` |

In the target channel exactly one cell is 1: the target's cell when it lies inside the window,
else the border cell it projects to (POGEMA's rule: each of `dx`, `dy` of the target from the
robot clamped to `-r..r`); all else 0. A robot on its target sees 1 in the centre.

`hint=True` (with `"local"`) then ends the row with 5 numbers, one per action (STAY, NORTH, EAST,
SOUTH, WEST): 1 where the action starts a shortest path (in moves, other robots ignored) to the
robot's own target, else 0; all 0 on the target and where it is out of reach. On levels without
puddles or glass walls these are the optimal actions of one robot alone. Worked out by one
breadth-first search per target cell, the first time a robot is given it, then kept; nothing
is planned per step.

`lifelong=True` (with `goals="own"`, POGEMA's lifelong task): a robot that reaches its target
gets the exit reward for that step and at once a new target, drawn from the env's generator
(a free cell reachable from where it stands, not that cell, none of the other robots' targets
while there are cells left), and keeps going: nobody finishes, and the race ends at `max_cycles`
(every robot truncated). `env.goals_reached` counts each robot's targets in the episode
(throughput: their sum over the steps).

`finished="stay"` (with `goals="own"`, POGEMA's `on_target="nothing"`, the rule of its
published maze runs): a robot on its target stays on the board and keeps racing: it earns the
exit reward (0 by default) for each step it ends there, may leave again, and blocks others as
any robot does; `infos[agent]["finished"]` says whether it stands on its target now, and so
does `env.goals_reached` (1 or 0). The race ends when every robot stands on its target at
once (all terminated) or after `max_cycles` steps (all truncated). `env.batch(n)` plays the
same races on the batch engine (all robots finish, staying on the board, when all stand on theirs).

## Episode end

The race ends when every robot has finished, or after `max_cycles` steps (the robots still
racing are truncated). With `finished="remove"` (default, the PettingZoo convention) a robot
leaves `agents` in the step it finishes; `step({})` with no agents left returns empty dicts.
With `finished="freeze"` finished robots stay in `agents`, parked off the board, with reward 0
and `terminated=False` (`infos[agent]["finished"]` is True), until the race ends, when they are
all terminated: every agent is present at every step, which SuperSuit's
`pettingzoo_env_to_vec_env_v1` needs. A parked robot is an absorbing state of reward 0, so
returns are the same as with "remove".

## Actions dict

Every racing agent needs an action: a missing one is a `ValueError` (give 0 for STAY), and
so is an unknown agent or an action outside 0..4 or not an integer. An action for a robot that
has already finished (removed or parked) is checked and ignored while the race runs, as
PettingZoo's own conversions do (AgileRL sends one for every possible agent). A rejected step
changes nothing. Once the race is over, `step({})` returns five empty dicts and a step with
actions is a `ValueError` asking for `reset()`; `step`, `set_cells` and `state()` before the
first `reset()` are a `RuntimeError`.

## Info

`infos[agent]` has the same keys after `reset` and every step, numbers only (tensor libraries
stack them):

| key        | type                 | meaning                                                                  |
|------------|----------------------|--------------------------------------------------------------------------|
| `cell`     | int64 array `[x, y]` | its cell (a finished robot: the exit it took, or its own target)         |
| `outcome`  | int                  | code into `babyrobot_marl.OUTCOME_NAMES` (below)                         |
| `blocked`  | bool                 | another robot stopped it this step                                       |
| `finished` | bool                 | it has reached an exit (`goals="own"`: its own target)                   |
| `rank`     | int                  | 0 until it finishes, then 1 = first (robots finishing together share it) |

Outcome codes: 0 moved, 1 stayed, 2 bumped, 3 skidded, 4 glass, 5 start (after reset), 6 finished (parked).

## Reset

`reset(seed=None, options=None)`: `seed` a non-negative integer (numpy integers too; bools and
floats are a `ValueError`). The generator is made at the first reset, so unseeded copies of an
env (SuperSuit's `concat_vec_envs_v1` clones it) play different races. `options={"starts":
[(x, y), ...]}` places the robots: one distinct open cell per robot (not blocked, not an exit);
a bad value is a `ValueError`. With `goals="own"`, `options={"goals": [(x, y), ...]}` gives the
targets (Own goals above); in the race to the exits it is a `ValueError`. Any other option key
is ignored with a `UserWarning` naming the known ones (PettingZoo's `api_test` resets with
`options={"options": 1}`).

## Arguments

```python
race_v0.parallel_env(level="race-2", n_robots=2, collisions="block", max_cycles=None,
                     start="level", finished="remove", rules=None, render_mode=None,
                     cell_size=32, theme="light", animation_frames=4, observe="global",
                     view_radius=None, k=None, obs_encoding="multidiscrete", hint=False, goals="exit",
                     lifelong=False, **rule_overrides)
```

* `level`: a built-in name (`babyrobot_marl.levels.names()`), a level text, a grid map (rows of
  `.` and `#`, or a MovingAI `.map` file's path: `Level.from_grid`; a level needs an exit) or a `Level`; or
  levels drawn at every reset from the env's seeded generator: `"maze:A..B"` (square mazes, the
  side drawn from `A..B`, e.g. `"maze:8..16"`; one size: `"maze:16..16"`), `"gridmaze:A..B"` (grid
  mazes of blocked cells with loops and no exit, for `goals="own"`), a maze family
  `"maze-WxH-*"`, `babyrobot_marl.levels.sources.maze_family(W, H, seeds=...)` or
  `maze_range_family(A, B, seeds=...)`, or a callable `f(np_random) -> Level | name | text` (one
  size for all); not for the batch and vector envs. With `"maze:A..B"` the env is built on a
  `BxB` maze: `W`, `H` in the observation spaces, `max_cycles` and the frame size are the
  largest level's (a smaller level's coordinates fit inside; its frames are its own size).
* `n_robots`: how many robots race (`robot_0` ... `robot_{n-1}`).
* `collisions`: `"block"`, `"bounce"`, `"pass"` or `"soft"` (overrides `rules.collisions`).
* `max_cycles`: steps before the race is truncated (default `max(100, 4 * W * H)`).
* `start`: `"level"` (the level's numbered starts; an error if it has fewer than
  `n_robots`), `"fill"` (the level's starts, then random free cells), `"random"` (random
  free cells each reset), drawn from the env's seeded generator.
* `finished`: `"remove"` or `"freeze"` (above).
* `observe`: `"global"`, `"local"` (with `view_radius`) or `"nearest"` (with `k`) (above);
  `view_radius` or `k` given to another mode is a `ValueError`.
* `hint`: `True` adds the goal hint to `"local"` rows (above); with another mode a `ValueError`.
* `goals`: `"exit"` (default: the race to the exits) or `"own"` (each robot its own target: Own goals above).
* `lifelong`: `True` (with `goals="own"`) gives a robot a new target each time it reaches one (above).
* `rules` / keyword overrides: any `Rules` field, e.g. `win_bonus=0`, `glass_pass_prob=1`; any
  other keyword is Python's own `TypeError` (`... got an unexpected keyword argument 'x'`).
* `obs_encoding`: `"multidiscrete"` (default), `"box"` or `"onehot"` (Observations above), for any `observe` mode.
* `render_mode`: `"ansi"` (text frame), `"rgb_array"` (`uint8[H * cell_size, W * cell_size, 3]`,
  pure numpy, each robot a disc in its own colour) or `"human"` (in Jupyter with the `notebook`
  extra: a live ipycanvas canvas, robots gliding over `animation_frames` frames per step, 0:
  jumping; elsewhere the text frame printed each step).
* `cell_size` (pixels, default 32) and `theme` (`"light"`, `"dark"`, `"mono"` or a `Theme`): style of
  the frames and the canvas. `env.unwrapped.set_overlay(values=..., arrows=..., text=..., panel=...)`
  draws over the grid (`babyrobot_marl.render.overlay`).

## Version history

* v0: first release.
"""

from __future__ import annotations

from typing import Any

from pettingzoo.utils import parallel_to_aec, wrappers

from .core.checks import check_action
from .envs.race import RaceEnv

__all__ = ["RaceEnv", "env", "parallel_env", "raw_env"]


def parallel_env(**kwargs: Any) -> RaceEnv:
    """The race as a PettingZoo ``ParallelEnv`` (see the module docstring for arguments)."""
    return RaceEnv(**kwargs)


def raw_env(**kwargs: Any):
    """The race in the AEC form, unwrapped."""
    return parallel_to_aec(parallel_env(**kwargs))


class CheckedActions(wrappers.BaseWrapper):
    """Checks each agent's action as it is given.

    ``parallel_to_aec`` collects a whole cycle of actions before the race steps: without this,
    a bad action would be found only at the end of the cycle, after being stored.
    """

    def step(self, action: Any) -> None:
        if action is not None:  # agents that are done step with None
            check_action(action, f"action of {self.agent_selection!r}")
        super().step(action)


def env(**kwargs: Any):
    """The race in the AEC form with PettingZoo's usual wrappers."""
    aec = wrappers.AssertOutOfBoundsWrapper(raw_env(**kwargs))
    return wrappers.OrderEnforcingWrapper(CheckedActions(aec))  # a clear ValueError before the assert
