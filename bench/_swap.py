"""Swap a function or module of pds_plugin for another wherever pds_plugin refers to it.

The engine scripts time kernels (``engine_profile.py``) and swap in the numba kernels
(``engine_vs_numba.py``) without knowing which module of the package calls which
kernel: every loaded ``pds_plugin`` module's attributes are matched by identity. Load
what will run first (mesh something small, with its certificate).
"""

from __future__ import annotations

import sys

KERNELS = ("_sampling_kernels", "_complex_kernels", "_geometry_kernels", "_mesh_kernels",
           "_certificate_kernels")


def replace_everywhere(old, new, skip=()) -> None:
    """Point every attribute of every loaded pds_plugin module (except the modules named
    in ``skip``) that is ``old`` at ``new``."""
    for name, module in list(sys.modules.items()):
        if (name == "pds_plugin" or name.startswith("pds_plugin.")) and name not in skip:
            for attribute, value in list(vars(module).items()):
                if value is old:
                    setattr(module, attribute, new)


def use_kernels(current: dict, wanted: dict) -> None:
    """Make pds_plugin call the kernel modules ``wanted`` (name -> module) instead of
    ``current``: the modules, the functions imported from them, and ``sys.modules`` for
    imports made inside functions."""
    skip = {f"pds_plugin.{name}" for name in KERNELS}
    for name in KERNELS:
        old, new = current[name], wanted[name]
        replace_everywhere(old, new, skip)
        for attribute, function in vars(old).items():         # the kernel functions
            if (not attribute.startswith("_") and callable(function)
                    and not isinstance(function, type) and hasattr(new, attribute)):
                replace_everywhere(function, getattr(new, attribute), skip)
        sys.modules[f"pds_plugin.{name}"] = new
