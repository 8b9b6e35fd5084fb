"""fabkit: design physical things out of parts and get a plan you can build.

``from fabkit.hacks import *`` gives the FabHaL language of the FabHacks paper.
"""

from ._fabkit import ConnectError, Error, Frame  # noqa: F401

__all__ = ["Error", "ConnectError", "Frame"]
__version__ = "0.1.0"
