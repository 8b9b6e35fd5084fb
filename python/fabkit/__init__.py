"""fabkit: design physical things out of parts and get a plan you can build.

``from fabkit.hacks import *`` gives the FabHaL language of the FabHacks paper. Every kit
raises the same exceptions: ``fabkit.Error`` and below it ``InputError`` (bad input; also a
``ValueError``), ``InfeasibleError`` (``ConnectError``), ``TimeLimitError`` and ``WriteError``.
"""

from ._fabkit import (  # noqa: F401
    ConnectError,
    Error,
    Frame,
    InfeasibleError,
    InputError,
    TimeLimitError,
    WriteError,
)

__all__ = [
    "Error", "InputError", "InfeasibleError", "ConnectError", "TimeLimitError", "WriteError",
    "Frame",
]
__version__ = "0.1.0"
