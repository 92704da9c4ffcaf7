"""Which key does what: terminal bytes, browser key names and pygame key codes to game commands.

A command is an ``Action`` (a move, or STAY) or one of the strings ``RESTART``, ``QUIT`` and
``SWITCH`` (drive the next robot of a race). Pure Python: importing this module needs no terminal,
no browser and no pygame.
"""

from __future__ import annotations

from ..core.actions import Action

RESTART, QUIT, SWITCH = "restart", "quit", "switch"
Command = Action | str

# Terminal input. Arrow keys arrive as escape sequences: CSI (ESC [ A) in the normal cursor mode,
# SS3 (ESC O A) in the application mode some terminals (and tmux) switch to.
TERMINAL_KEYS: dict[str, Command] = {
    "\x1b[A": Action.NORTH, "\x1bOA": Action.NORTH, "w": Action.NORTH, "W": Action.NORTH, "k": Action.NORTH,
    "\x1b[B": Action.SOUTH, "\x1bOB": Action.SOUTH, "s": Action.SOUTH, "S": Action.SOUTH, "j": Action.SOUTH,
    "\x1b[C": Action.EAST, "\x1bOC": Action.EAST, "d": Action.EAST, "D": Action.EAST, "l": Action.EAST,
    "\x1b[D": Action.WEST, "\x1bOD": Action.WEST, "a": Action.WEST, "A": Action.WEST, "h": Action.WEST,
    " ": Action.STAY, ".": Action.STAY,
    "r": RESTART, "R": RESTART,
    "q": QUIT, "Q": QUIT, "\x03": QUIT, "\x04": QUIT,  # Ctrl-C, Ctrl-D (when the terminal passes them as bytes)
    "\t": SWITCH,
}  # fmt: skip

# Browser ``KeyboardEvent.key`` names (ipycanvas sends them from a focused canvas).
BROWSER_KEYS: dict[str, Command] = {
    "ArrowUp": Action.NORTH, "w": Action.NORTH, "W": Action.NORTH,
    "ArrowDown": Action.SOUTH, "s": Action.SOUTH, "S": Action.SOUTH,
    "ArrowRight": Action.EAST, "d": Action.EAST, "D": Action.EAST,
    "ArrowLeft": Action.WEST, "a": Action.WEST, "A": Action.WEST,
    " ": Action.STAY, ".": Action.STAY,
    "r": RESTART, "R": RESTART,
    "Tab": SWITCH,
}  # fmt: skip

# SDL2 key codes (pygame 2's ``K_UP`` ...: SDLK_SCANCODE_MASK | scancode), fixed by SDL; written out
# so that the key map needs no pygame import. A test checks them against pygame's constants.
SDL_K_RIGHT, SDL_K_LEFT, SDL_K_DOWN, SDL_K_UP = 0x4000004F, 0x40000050, 0x40000051, 0x40000052

HELP = "arrows/WASD move, space stay, r restart, q quit"


def keys_to_action() -> dict[tuple[int, ...], int]:
    """``gymnasium.utils.play``'s key map: arrow keys and WASD move, space stays (pygame key codes)."""
    moves = {
        Action.NORTH: (SDL_K_UP, ord("w")),
        Action.SOUTH: (SDL_K_DOWN, ord("s")),
        Action.EAST: (SDL_K_RIGHT, ord("d")),
        Action.WEST: (SDL_K_LEFT, ord("a")),
        Action.STAY: (ord(" "),),
    }
    return {(key,): int(action) for action, keys in moves.items() for key in keys}


def decode(buffer: str) -> tuple[list[Command | None], str]:
    """Split terminal input into keys: ``(commands, rest)``; ``None`` for a key with no meaning here,
    ``rest`` an escape sequence cut short (wait for more input, or take it as a lone ESC)."""
    commands: list[Command | None] = []
    i, n = 0, len(buffer)
    while i < n:
        if buffer[i] != "\x1b":
            commands.append(TERMINAL_KEYS.get(buffer[i]))
            i += 1
            continue
        if i + 1 == n:
            return commands, buffer[i:]
        if buffer[i + 1] == "O":  # SS3: ESC O and one letter
            if i + 2 == n:
                return commands, buffer[i:]
            commands.append(TERMINAL_KEYS.get(buffer[i : i + 3]))
            i += 3
        elif buffer[i + 1] == "[":  # CSI: ESC [ parameters, then one final byte in @..~
            j = i + 2
            while j < n and not "@" <= buffer[j] <= "~":
                j += 1
            if j == n:
                return commands, buffer[i:]
            commands.append(TERMINAL_KEYS.get(buffer[i : j + 1]))
            i = j + 1
        else:  # ESC then another key (Alt+key): the key alone
            i += 1
    return commands, ""
