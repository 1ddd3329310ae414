"""Gymnasium environments on rrbody's table (the ``envs`` extra: gymnasium).

``import rrbody.envs`` registers ``rrbody/PushT-v0`` (:class:`rrbody.envs.pusht.PushTEnv`: Push-T, the
planar pushing task of Diffusion Policy, with the T on a table of exact dry friction; 300 actions per
episode, as gym-pusht registers it); ``gymnasium.make("rrbody.envs:rrbody/PushT-v0")`` imports and makes
it in one call. :func:`table` puts gym-pusht's own environment (or any pymunk environment meeting its
contract) on the same table.
"""
from __future__ import annotations

from typing import Any

from rrbody.model.extras import require

gymnasium = require("gymnasium", purpose="rrbody.envs (the gymnasium environments)")

__all__ = ["PushTEnv", "table"]

ENV_ID = "rrbody/PushT-v0"
if ENV_ID not in gymnasium.registry:
    gymnasium.register(id=ENV_ID, entry_point="rrbody.envs.pusht:PushTEnv", max_episode_steps=300)


def __getattr__(name: str) -> Any:
    # the environment and the wrapper load on first use: importing rrbody.envs only registers
    if name == "PushTEnv":
        from rrbody.envs.pusht import PushTEnv

        return PushTEnv
    if name == "table":
        from rrbody.envs.wrapper import table

        return table
    raise AttributeError(f"module 'rrbody.envs' has no attribute {name!r}")
