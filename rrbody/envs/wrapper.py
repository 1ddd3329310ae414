"""A gymnasium wrapper that puts a pymunk environment on rrbody's table: exact Coulomb friction.

::

    import gymnasium, gym_pusht
    from rrbody.envs import table

    env = table(gymnasium.make("gym_pusht/PushT-v0"), mu=0.3)   # the T slides, then stops
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    env.plane.friction(env.unwrapped.block)                     # the friction force and torque now

gym-pusht sets ``space.damping = 0``: pymunk multiplies every velocity by ``damping**dt`` in each step, so
the T stops as soon as the agent leaves it. The wrapper replaces that wipe by the table: after each reset,
the area-integrated Coulomb friction of :class:`rrbody.engine.plugin.plane.PlaneFriction` on the space's bodies,
damping 1 where it was 0, and ``plane.step(dt)`` for the environment's ``space.step(dt)``. Observations,
actions, rewards and spaces are the environment's own. The contract, :data:`CONTRACT`: docs/envs-table.md.
"""
from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any, SupportsFloat

import gymnasium
import pymunk
from gymnasium.utils import RecordConstructorArgs

from rrbody.engine.plugin import PlaneFriction
from rrbody.envs.substep import guarded
from rrbody.envs.tabletop import MU, SCALE, G, Table, make_table

__all__ = ["CONTRACT", "TableSpace", "TableWrapper", "table"]

#: What the wrapper needs of an environment (quoted by its errors).
CONTRACT = ("env.unwrapped must keep its pymunk.Space in a settable attribute `space`, advance it only through "
            "space.step(dt), and may replace it in reset")

#: ``bodies``: env.unwrapped -> the bodies the table carries, called after every reset.
BodyPicker = Callable[[Any], Iterable[Any]]


class TableSpace:
    """The environment's space with the table under it: what the wrapper puts in ``env.unwrapped.space``.

    ``step(dt)`` (dt in s, > 0) is ``step``, by default ``plane.step`` itself (a callable kept in a slot: no
    call of this class's in between, as the environment calls it ten times per ``env.step``): the table's
    friction on its bodies, then the real space's ``step(dt)``; the wrapper gives it
    :func:`rrbody.envs.substep.guarded`'s, which cuts a step into sub-steps where a body would cross more
    than a wall's thickness in it. Every other attribute is read from, written to and
    deleted on the real ``pymunk.Space`` (``bodies``, ``add``, ``debug_draw``, ``add_collision_handler``,
    ``damping``, ...). It is not itself a ``pymunk.Space``: ``body.space`` is the real one (``plane.space``).
    """

    __slots__ = ("_space", "_plane", "step")

    def __init__(self, plane: Any, step: Any = None) -> None:  # a rrbody.engine.plugin.plane.PlaneFriction
        # object.__setattr__: this class's own __setattr__ writes to the real space
        object.__setattr__(self, "_space", plane.space)
        object.__setattr__(self, "_plane", plane)
        object.__setattr__(self, "step", plane.step if step is None else step)

    def __getattr__(self, name: str) -> Any:
        # only names this class does not define arrive here; object.__getattribute__ so that a half-built
        # proxy (copy, pickle) raises AttributeError instead of recursing
        return getattr(object.__getattribute__(self, "_space"), name)

    def __setattr__(self, name: str, value: Any) -> None:
        setattr(self._space, name, value)

    def __delattr__(self, name: str) -> None:
        delattr(self._space, name)

    def __dir__(self) -> list[str]:
        return sorted(set(dir(self._space)) | {"step"})

    def __repr__(self) -> str:
        return f"TableSpace({self._space!r})"


class TableWrapper(gymnasium.Wrapper[Any, Any, Any, Any], RecordConstructorArgs):
    """``env`` on a table: :func:`table` (the same keywords, checked here, before anything changes).

    After every ``reset`` of ``env``: a new :class:`~rrbody.engine.plugin.plane.PlaneFriction` on
    ``env.unwrapped.space`` (pressing with ``table.g_space`` = g / scale, units/s^2), carrying the table's bodies
    with ``mu``, ``mu_static`` and ``pressure``; the space's damping set to 1 if it was 0 (any other value is kept);
    and :class:`TableSpace` in ``env.unwrapped.space``. Before every ``reset`` the environment gets its own space
    back, with its own damping, so its reset runs exactly as without the table.

    It records its keywords as gymnasium's wrappers do (``gymnasium.utils.RecordConstructorArgs``), so
    that ``env.spec`` makes it again (``gymnasium.make(env.spec)``, the checker's ``check_env``).
    """

    def __init__(self, env: gymnasium.Env[Any, Any], *, mu: float = MU, mu_static: float | None = None,
                 pressure: Any = "uniform", g: float = G, scale: float = SCALE,
                 bodies: BodyPicker | None = None) -> None:
        table = _check(env, mu, mu_static, pressure, g, scale, bodies)
        # the keywords as given (no deep copy: a bound method's deep copy would copy its object)
        RecordConstructorArgs.__init__(self, _disable_deepcopy=True, mu=mu, mu_static=mu_static, pressure=pressure,
                                       g=g, scale=scale, bodies=bodies)
        gymnasium.Wrapper.__init__(self, env)
        self._table = table
        self._pick = bodies
        self._plane: PlaneFriction | None = None
        self._proxy: TableSpace | None = None
        self._base: Any = None  # env.unwrapped at the last reset (step reads its space without the wrapper chain)
        self._env_damping = 0.0  # the damping the environment set, restored before its next reset

    @property
    def table(self) -> Table:
        """The table's checked parameters (mu, mu_static, pressure, g in m/s^2, scale in m per unit)."""
        return self._table

    @property
    def plane(self) -> Any:  # a rrbody.engine.plugin.plane.PlaneFriction (the docs' type reference needs no name clash)
        """The table's friction on the current space (a new one after every reset): ``plane.bodies``,
        ``plane.friction(body)``, ``plane.velocity(body)``, ``plane.stop_time(body)``, ``plane.space``
        (the real ``pymunk.Space``). Raises ``gymnasium.error.ResetNeeded`` before the first reset."""
        if self._plane is None:
            raise gymnasium.error.ResetNeeded("there is no table before the first reset (the environment builds "
                                              "its pymunk space in reset): call env.reset() first")
        return self._plane

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        """Reset ``env`` (its own space and damping, no table: its reset observation is unchanged), then
        put the table under the space it left."""
        u = self.env.unwrapped
        if self._plane is not None and getattr(u, "space", None) is self._proxy:
            # an environment that keeps its space across resets steps it in its reset as if never wrapped
            u.space = self._plane.space
            self._plane.space.damping = self._env_damping
        self._plane = self._proxy = None  # a reset that raises leaves the wrapper needing one
        obs, info = self.env.reset(seed=seed, options=options)
        self._install(u)
        return obs, info

    def step(self, action: Any) -> tuple[Any, SupportsFloat, bool, bool, dict[str, Any]]:
        """``env.step(action)``, its space stepped by the table; raises ``gymnasium.error.ResetNeeded``
        before the first reset, and ``ValueError`` if the environment replaced its space since the last
        reset (the new space would have no table)."""
        if self._proxy is None:
            raise gymnasium.error.ResetNeeded("cannot step a table wrapper before reset: call env.reset() first")
        space = getattr(self._base, "space", None)
        if space is not self._proxy:
            raise ValueError(f"env.unwrapped.space was replaced outside reset (it is now {space!r}), so the table "
                             f"is no longer under it: {CONTRACT}")
        return self.env.step(action)

    def _install(self, u: Any) -> None:
        """The table under ``u.space``; on an error nothing of the space has changed."""
        space = _space_of(u, when="after reset")
        if space is None:  # table() let it pass if it had none at wrap time either: the check waited for reset
            raise TypeError(f"env.unwrapped ({type(u).__name__}) has no attribute 'space' after reset: {CONTRACT}")
        plane = PlaneFriction(space, g=self._table.g_space)
        t = self._table
        carried = self._carried(u, space)
        for i, body in enumerate(carried):
            try:
                plane.add(body, mu=t.mu, mu_static=t.mu_static, pressure=t.pressure)
            except ValueError as e:  # PlaneFriction names the body's fault; say which body of the env it is
                which = f"bodies(env.unwrapped)[{i}]" if self._pick else "a dynamic body of env.unwrapped.space"
                raise ValueError(f"{which} ({body!r}) cannot go on the table: {e}") from e
        # the bodies keep their momentum on the table: sub-steps where one would cross more than a wall in one step
        proxy = TableSpace(plane, guarded(plane.step, carried, space))
        try:
            u.space = proxy
        except AttributeError as e:  # a read-only property
            raise TypeError(f"env.unwrapped.space of {type(u).__name__} cannot be set ({e}): {CONTRACT}") from None
        self._env_damping = space.damping
        if space.damping == 0.0:
            # the velocity wipe: the table now takes the velocity away, over the time friction needs
            space.damping = 1.0
        self._plane, self._proxy, self._base = plane, proxy, u

    def _carried(self, u: Any, space: pymunk.Space) -> list[pymunk.Body]:
        """The bodies the table carries: ``bodies(u)``, or every dynamic body of ``space`` with a shape."""
        if self._pick is None:
            return [b for b in space.bodies if b.body_type == pymunk.Body.DYNAMIC and b.shapes]
        got = self._pick(u)
        if isinstance(got, pymunk.Body) or not isinstance(got, Iterable):
            raise TypeError(f"bodies(env.unwrapped) must return an iterable of pymunk.Body, got {got!r}")
        out = list(got)
        for b in out:
            if not isinstance(b, pymunk.Body):
                raise TypeError(f"bodies(env.unwrapped) must return pymunk.Body objects only, got {b!r}")
        return out


def _space_of(u: Any, *, when: str) -> pymunk.Space | None:
    """``u.space`` if it is a ``pymunk.Space``, None if ``u`` has no ``space``; TypeError for anything else."""
    space = getattr(u, "space", None)
    if space is None or isinstance(space, pymunk.Space):
        return space
    if isinstance(space, TableSpace):
        raise ValueError(f"env is already on a table (its space is {space!r} {when}): apply table() once")
    raise TypeError(f"env.unwrapped.space must be a pymunk.Space, got {type(space).__name__} {when}: {CONTRACT}")


def table(env: gymnasium.Env[Any, Any], *, mu: float = MU, mu_static: float | None = None,
          pressure: Any = "uniform", g: float = G, scale: float = SCALE,
          bodies: BodyPicker | None = None) -> TableWrapper:
    """Put ``env`` (gym-pusht's Push-T, or any environment that meets :data:`CONTRACT`) on a table.

    Parameters
    ----------
    env : gymnasium.Env
        The environment, bare or wrapped (``gymnasium.make(...)``); ``env.unwrapped`` keeps its
        ``pymunk.Space`` in ``space``, steps it only through ``space.step(dt)``, and may build a new one in
        ``reset``.
    mu : float
        Kinetic friction coefficient, >= 0 (dimensionless; default 0.3, PLA on a wooden table).
    mu_static : float or None
        Static friction coefficient, >= mu (None: equal to mu). A body at rest stays exactly at rest
        while the load on it stays inside its limit surface for mu_static.
    pressure : str or rrbody.pressure profile
        How each body's weight presses on the table (:mod:`rrbody.pressure`; default "uniform": each
        shape's weight over its own area, centred on the body's centre of gravity).
    g : float
        Gravitational acceleration, m/s^2, > 0.
    scale : float
        Length of one unit of the environment's space, m per unit, > 0 (default 1/600: gym-pusht's T is
        the 0.2 m real-robot T of Diffusion Policy). The plane presses with g / scale units/s^2.
    bodies : callable or None
        ``bodies(env.unwrapped)`` -> the ``pymunk.Body`` objects on the table, called after every reset
        (None: every dynamic body of the space that has a shape; gym-pusht: the T, its agent being
        kinematic).

    Returns
    -------
    TableWrapper
        ``env`` with the table, its observations, actions, rewards and spaces unchanged; ``.plane`` is
        the current :class:`~rrbody.engine.plugin.plane.PlaneFriction`, ``.table`` the parameters.

    Raises
    ------
    ValueError
        Naming the parameter, its value and the valid range, for ``mu``, ``mu_static``, ``pressure``, ``g``
        or ``scale`` (:func:`rrbody.envs.tabletop.make_table`), or for an ``env`` already on a table.
    TypeError
        For an ``env`` that is not a gymnasium.Env, a ``bodies`` that is not callable, or an
        ``env.unwrapped.space`` that is not a pymunk.Space. An environment with no ``space`` yet (gym-pusht
        builds its space in ``reset``) is checked at the first reset instead, which raises this TypeError
        if it left no ``pymunk.Space`` there. Nothing changes when one of these is raised.
    """
    return TableWrapper(env, mu=mu, mu_static=mu_static, pressure=pressure, g=g, scale=scale, bodies=bodies)


def _check(env: Any, mu: Any, mu_static: Any, pressure: Any, g: Any, scale: Any, bodies: Any) -> Table:
    """:func:`table`'s arguments checked (the errors its docstring lists); the table's parameters."""
    if not isinstance(env, gymnasium.Env):
        raise TypeError(f"env must be a gymnasium.Env, got {type(env).__name__}: {CONTRACT}")
    params = make_table(mu, mu_static, pressure, g, scale)
    if bodies is not None and not callable(bodies):
        raise TypeError(f"bodies must be None or a callable env.unwrapped -> list of pymunk.Body, got {bodies!r}")
    e: Any = env
    while isinstance(e, gymnasium.Wrapper):
        if isinstance(e, TableWrapper):
            raise ValueError(f"env is already on a table ({e!r}): apply table() once")
        e = e.env
    if isinstance(getattr(env.unwrapped, "table", None), Table):
        # rrbody/PushT-v0 with its own table steps it itself: a second one would never be stepped
        raise ValueError(f"env is already on a table (rrbody/PushT-v0's own, {env.unwrapped.table!r}): make it with "
                         f"table=False to put it on this one, or use its own")
    _space_of(env.unwrapped, when="at wrap time")  # absent (gym-pusht before its first reset): checked after reset
    return params
