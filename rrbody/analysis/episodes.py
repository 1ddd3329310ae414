"""Reverse-rotation episodes in sampled runs: a body turning against its orbital sense.

One definition for the collision scenes (driven bodies, ``scenes/collisions.py``: the angle is phi,
the orbit the drive's, counter-clockwise) and for active bodies (``scenes/active.py``: the body angle,
the orbit the sense of the circle the body swims alone, the sign of its propulsion's torque):

    An episode is a maximal run of consecutive samples with sense * rate < 0 (the spin opposite to the
    orbital sense) over which sense * angle falls by more than ``min_turn`` (rad; default pi: at least
    half a turn backwards). It lasts from its first to its last sample (s); it *began at a collision*
    if the body began a contact at a time in [t_start - window, t_start], t_start its first sample
    (the contact's impulse precedes the first sample with the reversed spin).

``min_turn`` keeps brief jitters of the spin about zero (noise, a glancing contact) from counting:
the body must actually have turned back. Samples are taken as given: an episode shorter than the
sampling interval, or one that turned back less than ``min_turn``, is not reported.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

__all__ = ["reverse_episodes", "episode_marks"]


def reverse_episodes(t: np.ndarray, angle: np.ndarray, rate: np.ndarray, *, sense: float = 1.0,
                     min_turn: float = math.pi, hits: Sequence[float] = (), window: float = 1.0) -> list[dict]:
    """The episodes (module docstring) of one body sampled at times ``t`` (s): ``angle`` unwrapped (rad),
    ``rate`` its derivative (rad/s), ``sense`` the orbital sense (+1 counter-clockwise, -1 clockwise),
    ``hits`` the times its contacts began (s). Each episode: ``t_start``, ``t_end`` (s), ``duration``
    (s), ``turns_back`` (revolutions turned against the orbit), ``starts_at_collision`` (bool)."""
    if sense not in (1.0, -1.0, 1, -1):
        raise ValueError(f"sense must be +1 or -1, got {sense!r}")
    a = sense * np.asarray(angle, dtype=float)
    back = sense * np.asarray(rate, dtype=float) < 0.0
    hit = np.sort(np.asarray(hits, dtype=float))
    out: list[dict] = []
    # maximal runs of reversed samples: starts where back turns on, ends where it turns off
    edges = np.flatnonzero(np.diff(np.concatenate(([0], back.astype(np.int8), [0]))))
    for i, j in zip(edges[::2], edges[1::2] - 1):
        drop = a[i] - a[j]
        if drop > min_turn:
            k = np.searchsorted(hit, t[i] - window, side="left")
            at_hit = bool(k < len(hit) and hit[k] <= t[i] + 1e-9)
            out.append({"t_start": float(t[i]), "t_end": float(t[j]), "duration": float(t[j] - t[i]),
                        "turns_back": float(drop / (2 * math.pi)), "starts_at_collision": at_hit})
    return out


def episode_marks(t: np.ndarray, rate: np.ndarray, episodes: Sequence[dict], *, sense: float = 1.0) -> np.ndarray:
    """Per sample: -1 inside an established episode, +1 where the body turns with its orbit, 0 elsewhere
    (reversed but not an episode, or no spin): the marks a movie colours by (red, blue, grey)."""
    m = np.where(sense * np.asarray(rate) > 0.0, 1.0, 0.0)
    for e in episodes:
        m[(t >= e["t_start"]) & (t <= e["t_end"])] = -1.0
    return m
