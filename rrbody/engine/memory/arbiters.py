"""The contacts pymunk solved in a step, for the coupled step (:mod:`rrbody.engine.plugin.coupling`): two routes to one
result, the raw point and body rows of :mod:`rrbody.contact.islands`.

- ``"public"``: pymunk's Python API, ``body.each_arbiter`` on each body of the plugin and each arbiter's
  shapes, normal, points, friction, restitution and surface velocity (a Python call each: about 9 us per
  contact on pymunk 7);
- ``"compiled"``: the same numbers from Chipmunk's own C functions (``cpBodyEachArbiter``, ``cpArbiterGet*``,
  ``cpBodyGet*``; no struct layout), called from compiled code through the addresses pymunk's cffi module
  gives them (``pymunk._chipmunk``, which pymunk does not document), and the velocities written back through
  ``cpBodySetVelocity`` and ``cpBodySetAngularVelocity``. Where a C function returns a struct of two doubles,
  the call follows the platform's C calling convention for it (two floating-point registers on x86-64 and
  ARM64 under Linux and macOS; not on Windows, where this route is not taken). A probe (:func:`compiled_route`)
  reads a scene of every kind of contact through both routes and writes a velocity back; the compiled route
  is taken only where both give the same bits, and never with ``RRBODY_NO_PRIVATE=1``
  (``tests/test_coupled_routes.py`` steps scenes on both routes and compares the bits).

Chipmunk's ``cpArbiterGetPointA``/``B`` return the points of its own first and second body whatever the order
an iterator hands the arbiter over in, while its normal follows that order; the compiled reader tells which
is which from the sign of the point's depth along the normal (``cpArbiterGetDepth``, in Chipmunk's own
order): where the depth is zero the two points coincide.
"""

from __future__ import annotations

import math
import platform
import sys
from typing import Any

import numpy as np
from llvmlite import ir
from numba import cfunc, njit, types
from numba.extending import intrinsic

from rrbody._private import private_allowed
from rrbody.contact import islands as I
from rrbody.contact.kernel import find_row
from rrbody.engine.memory.bodymem import address, i64_at

__all__ = ["ROUTES", "read_public", "write_public", "touching", "read_compiled", "write_compiled", "space_loads",
           "step_compiled",
           "compiled_route", "CompiledRoute"]

#: the routes to the contacts, fastest first
ROUTES = ("compiled", "public")

# ---- calls through C function addresses ----------------------------------------------------------
_I64 = ir.IntType(64)
_F64 = ir.DoubleType()
_VEC = ir.LiteralStructType([_F64, _F64])  # cpVect returned by value: two doubles


def _fn(builder: Any, addr: Any, ret: Any, args: list[Any]) -> Any:
    return builder.inttoptr(addr, ir.FunctionType(ret, args).as_pointer())


@intrinsic
def _v_iii(typingctx: Any, fn: Any, a: Any, b: Any, c: Any) -> Any:
    """void fn(ptr, ptr, ptr)."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        builder.call(_fn(builder, args[0], ir.VoidType(), [_I64, _I64, _I64]), [args[1], args[2], args[3]])
        return context.get_dummy_value()
    return types.none(types.int64, types.int64, types.int64, types.int64), codegen


@intrinsic
def _vec_i(typingctx: Any, fn: Any, a: Any) -> Any:
    """cpVect fn(ptr)."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        r = builder.call(_fn(builder, args[0], _VEC, [_I64]), [args[1]])
        return context.make_tuple(builder, sig.return_type, [builder.extract_value(r, 0), builder.extract_value(r, 1)])
    return types.UniTuple(types.float64, 2)(types.int64, types.int64), codegen


@intrinsic
def _vec_ii(typingctx: Any, fn: Any, a: Any, i: Any) -> Any:
    """cpVect fn(ptr, int)."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        f = _fn(builder, args[0], _VEC, [_I64, ir.IntType(32)])
        r = builder.call(f, [args[1], builder.trunc(args[2], ir.IntType(32))])
        return context.make_tuple(builder, sig.return_type, [builder.extract_value(r, 0), builder.extract_value(r, 1)])
    return types.UniTuple(types.float64, 2)(types.int64, types.int64, types.int64), codegen


@intrinsic
def _d_i(typingctx: Any, fn: Any, a: Any) -> Any:
    """double fn(ptr)."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.call(_fn(builder, args[0], _F64, [_I64]), [args[1]])
    return types.float64(types.int64, types.int64), codegen


@intrinsic
def _d_ii(typingctx: Any, fn: Any, a: Any, i: Any) -> Any:
    """double fn(ptr, int)."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        f = _fn(builder, args[0], _F64, [_I64, ir.IntType(32)])
        return builder.call(f, [args[1], builder.trunc(args[2], ir.IntType(32))])
    return types.float64(types.int64, types.int64, types.int64), codegen


@intrinsic
def _i32_i(typingctx: Any, fn: Any, a: Any) -> Any:
    """int fn(ptr) (an int or an enum), widened."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.sext(builder.call(_fn(builder, args[0], ir.IntType(32), [_I64]), [args[1]]), _I64)
    return types.int64(types.int64, types.int64), codegen


@intrinsic
def _u8_i(typingctx: Any, fn: Any, a: Any) -> Any:
    """unsigned char fn(ptr) (Chipmunk's cpBool), widened."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.zext(builder.call(_fn(builder, args[0], ir.IntType(8), [_I64]), [args[1]]), _I64)
    return types.int64(types.int64, types.int64), codegen


@intrinsic
def _p_i(typingctx: Any, fn: Any, a: Any) -> Any:
    """void *fn(ptr), as an int64."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.call(_fn(builder, args[0], _I64, [_I64]), [args[1]])
    return types.int64(types.int64, types.int64), codegen


@intrinsic
def _v_ivec(typingctx: Any, fn: Any, a: Any, x: Any, y: Any) -> Any:
    """void fn(ptr, cpVect) (a struct of two doubles passed by value: two floating-point registers)."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        builder.call(_fn(builder, args[0], ir.VoidType(), [_I64, _F64, _F64]), [args[1], args[2], args[3]])
        return context.get_dummy_value()
    return types.none(types.int64, types.int64, types.float64, types.float64), codegen


@intrinsic
def _v_id(typingctx: Any, fn: Any, a: Any, x: Any) -> Any:
    """void fn(ptr, double)."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        builder.call(_fn(builder, args[0], ir.VoidType(), [_I64, _F64]), [args[1], args[2]])
        return context.get_dummy_value()
    return types.none(types.int64, types.int64, types.float64), codegen


@intrinsic
def _addr(typingctx: Any, p: Any) -> Any:
    """A C pointer as an int64."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.ptrtoint(args[0], _I64)
    return types.int64(types.voidptr), codegen


@intrinsic
def _store(typingctx: Any, a: Any, v: Any) -> Any:
    """Store the int64 v at byte address a."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        builder.store(args[1], builder.inttoptr(args[0], _I64.as_pointer()))
        return context.get_dummy_value()
    return types.none(types.int64, types.int64), codegen


@intrinsic
def _bits(typingctx: Any, x: Any) -> Any:
    """A float64's bits as an int64."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.bitcast(args[0], _I64)
    return types.int64(types.float64), codegen


@intrinsic
def _float(typingctx: Any, x: Any) -> Any:
    """An int64's bits as a float64."""
    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.bitcast(args[0], _F64)
    return types.float64(types.int64), codegen


# the C functions the compiled route calls, in the order of its address table
_API = ("cpBodyEachArbiter", "cpArbiterGetNormal", "cpArbiterGetSurfaceVelocity", "cpArbiterGetBodies",
        "cpArbiterGetShapes", "cpShapeGetSensor", "cpArbiterGetCount", "cpArbiterGetPointA", "cpArbiterGetPointB",
        "cpArbiterGetDepth", "cpArbiterGetFriction", "cpArbiterGetRestitution", "cpBodyGetUserData", "cpBodyGetType",
        "cpBodyGetPosition", "cpBodyGetCenterOfGravity", "cpBodyGetAngle", "cpBodyGetVelocity",
        "cpBodyGetAngularVelocity", "cpBodyEachConstraint", "cpBodySetVelocity", "cpBodySetAngularVelocity",
        "cpSpaceGetGravity", "cpSpaceGetDamping")
(EACH_ARBITER, GET_NORMAL, GET_SURFACE_V, GET_BODIES, GET_SHAPES, SHAPE_SENSOR, GET_COUNT, GET_POINT_A, GET_POINT_B,
 GET_DEPTH, GET_FRICTION, GET_RESTITUTION, BODY_ID, BODY_TYPE, BODY_POSITION, BODY_COG, BODY_ANGLE, BODY_V, BODY_W,
 EACH_CONSTRAINT, SET_V, SET_W, SPACE_GRAVITY, SPACE_DAMPING, ON_ARBITER, ON_CONSTRAINT, ON_ANY) = range(len(_API) + 3)
#: Chipmunk's body types (cpBodyType)
_DYNAMIC, _KINEMATIC, _STATIC = 0, 1, 2
#: a record of the arbiter callback: the arbiter, the body handing it over, the normal and surface velocity
#: seen from that body (their bits)
_REC = 6


@cfunc(types.void(types.voidptr, types.voidptr, types.voidptr), cache=True)
def _on_arbiter(body: Any, arb: Any, data: Any) -> None:
    """cpBodyEachArbiter's callback: append (arbiter, body, normal and surface velocity as this body sees them:
    Chipmunk hands the arbiter over with ``body`` first only here) to the record at ``data``: int64s
    (count, capacity, the two getters' addresses, records...)."""
    d = _addr(data)
    n = i64_at(d)
    if n < i64_at(d + 8):
        a = _addr(arb)
        nx, ny = _vec_i(i64_at(d + 16), a)
        sx, sy = _vec_i(i64_at(d + 24), a)
        r = d + 32 + 8 * _REC * n
        _store(r, a)
        _store(r + 8, _addr(body))
        _store(r + 16, _bits(nx))
        _store(r + 24, _bits(ny))
        _store(r + 32, _bits(sx))
        _store(r + 40, _bits(sy))
    _store(d, n + 1)


@cfunc(types.void(types.voidptr, types.voidptr, types.voidptr), cache=True)
def _on_constraint(body: Any, constraint: Any, data: Any) -> None:
    """cpBodyEachConstraint's callback: count the constraints at ``data`` (an int64)."""
    d = _addr(data)
    _store(d, i64_at(d) + 1)


@njit(cache=True)
def _body_state(api: np.ndarray, b: int, out: np.ndarray) -> None:
    """A body's centre of gravity (world, m), angle, velocity and spin into ``out`` (RB_CGX .. RB_SPIN)."""
    px, py = _vec_i(api[BODY_POSITION], b)
    cx, cy = _vec_i(api[BODY_COG], b)
    a = _d_i(api[BODY_ANGLE], b)
    c = math.cos(a)
    s = math.sin(a)
    out[I.RB_CGX] = px + c * cx - s * cy
    out[I.RB_CGY] = py + s * cx + c * cy
    out[I.RB_ANGLE] = a
    out[I.RB_VX], out[I.RB_VY] = _vec_i(api[BODY_V], b)
    out[I.RB_SPIN] = _d_i(api[BODY_W], b)


@cfunc(types.void(types.voidptr, types.voidptr, types.voidptr), cache=True)
def _on_any(body: Any, arb: Any, data: Any) -> None:
    """cpBodyEachArbiter's callback: count the arbiters at ``data`` (an int64)."""
    d = _addr(data)
    _store(d, i64_at(d) + 1)


@njit(cache=True)
def touching(api: np.ndarray, addrs: np.ndarray, count: np.ndarray) -> bool:
    """Whether any plugin body (``addrs``: their cpBody addresses) touched something in the last step: the
    cheap first look of a step after one that touched nothing (``count``: one int64 of scratch)."""
    for j in range(addrs.shape[0]):
        count[0] = 0
        _v_iii(api[EACH_ARBITER], addrs[j], api[ON_ANY], count.ctypes.data)
        if count[0] > 0:
            return True
    return False


@njit(cache=True)
def read_compiled(api: np.ndarray, addrs: np.ndarray, lookup: np.ndarray, rec: np.ndarray, raw: np.ndarray,
                  body: np.ndarray) -> int:
    """The compiled route's read of every contact of the plugin's bodies (``addrs``: their cpBody addresses by
    plugin row; ``lookup``: the plugin's sorted id table) into ``raw`` and ``body`` (:mod:`rrbody.contact.islands`).
    Returns the raw point rows written, or minus the records or points needed where ``rec`` or ``raw`` is too
    small (nothing usable written then: the caller makes them larger and calls again)."""
    body[:, I.RB_SEEN] = 0.0
    rec[0] = 0
    rec[1] = (rec.shape[0] - 4) // _REC
    rec[2] = api[GET_NORMAL]
    rec[3] = api[GET_SURFACE_V]
    for j in range(addrs.shape[0]):
        _v_iii(api[EACH_ARBITER], addrs[j], api[ON_ARBITER], rec.ctypes.data)
    n_rec = rec[0]
    if n_rec > rec[1]:
        return -n_rec
    pair = np.zeros(2, dtype=np.int64)
    count = np.zeros(1, dtype=np.int64)
    n_raw = 0
    for r in range(n_rec):
        base = 4 + _REC * r
        arb = rec[base]
        x = rec[base + 1]  # the plugin body that handed the arbiter over, first in this record's view
        jx = find_row(lookup, _p_i(api[BODY_ID], x))
        _v_iii(api[GET_BODIES], arb, pair.ctypes.data, pair.ctypes.data + 8)
        other = pair[1] if pair[0] == x else pair[0]
        jo = find_row(lookup, _p_i(api[BODY_ID], other))
        if jo >= 0 and jo < jx:
            continue  # an arbiter of two plugin bodies: taken once, from the one with the lower row
        _v_iii(api[GET_SHAPES], arb, pair.ctypes.data, pair.ctypes.data + 8)
        if _u8_i(api[SHAPE_SENSOR], pair[0]) != 0 or _u8_i(api[SHAPE_SENSOR], pair[1]) != 0:
            continue
        n_pts = _i32_i(api[GET_COUNT], arb)
        if n_pts == 0:
            continue
        if n_raw + n_pts > raw.shape[0]:
            return -(n_raw + n_pts + 4 * (n_rec - r))
        nx = _float(rec[base + 2])
        ny = _float(rec[base + 3])
        kind = I.KIND_PLANE
        if jo < 0:
            t = _i32_i(api[BODY_TYPE], other)
            kind = I.KIND_STATIC if t == _STATIC else I.KIND_KINEMATIC if t == _KINEMATIC else I.KIND_OFF
        if body[jx, I.RB_SEEN] == 0.0:
            _body_state(api, x, body[jx])
            count[0] = 0
            _v_iii(api[EACH_CONSTRAINT], x, api[ON_CONSTRAINT], count.ctypes.data)
            body[jx, I.RB_JOINT] = 1.0 if count[0] > 0 else 0.0
            body[jx, I.RB_SEEN] = 1.0
        if jo >= 0 and body[jo, I.RB_SEEN] == 0.0:
            _body_state(api, other, body[jo])
            count[0] = 0
            _v_iii(api[EACH_CONSTRAINT], other, api[ON_CONSTRAINT], count.ctypes.data)
            body[jo, I.RB_JOINT] = 1.0 if count[0] > 0 else 0.0
            body[jo, I.RB_SEEN] = 1.0
        fixed = np.zeros(I.N_RB)
        if jo < 0:
            _body_state(api, other, fixed)
        for i in range(n_pts):
            p1x, p1y = _vec_ii(api[GET_POINT_A], arb, i)
            p2x, p2y = _vec_ii(api[GET_POINT_B], arb, i)
            depth = _d_ii(api[GET_DEPTH], arb, i)
            # the point on x's surface: Chipmunk's first body's point where the depth reads the same along x's
            # normal (x is its first body), else its second's; where the depth is zero they coincide
            c = (p2x - p1x) * nx + (p2y - p1y) * ny
            x_first = not (c * depth < 0.0)
            row = raw[n_raw]
            row[I.RP_A] = jx
            row[I.RP_B] = jo
            row[I.RP_KIND] = kind
            row[I.RP_NX] = nx
            row[I.RP_NY] = ny
            row[I.RP_POINT_AX] = p1x if x_first else p2x
            row[I.RP_POINT_AY] = p1y if x_first else p2y
            row[I.RP_POINT_BX] = p2x if x_first else p1x
            row[I.RP_POINT_BY] = p2y if x_first else p1y
            row[I.RP_FRICTION] = _d_i(api[GET_FRICTION], arb)
            row[I.RP_RESTITUTION] = _d_i(api[GET_RESTITUTION], arb)
            row[I.RP_SURFACE_VX] = _float(rec[base + 4])
            row[I.RP_SURFACE_VY] = _float(rec[base + 5])
            row[I.RP_B_VX] = fixed[I.RB_VX] if jo < 0 else 0.0
            row[I.RP_B_VY] = fixed[I.RB_VY] if jo < 0 else 0.0
            row[I.RP_B_SPIN] = fixed[I.RB_SPIN] if jo < 0 else 0.0
            row[I.RP_B_CGX] = fixed[I.RB_CGX] if jo < 0 else 0.0
            row[I.RP_B_CGY] = fixed[I.RB_CGY] if jo < 0 else 0.0
            n_raw += 1
    return n_raw


@njit(cache=True)
def write_compiled(api: np.ndarray, addrs: np.ndarray, order: np.ndarray, vel: np.ndarray) -> None:
    """Set the velocity and spin of the plugin bodies of rows ``order`` to ``vel`` (m/s, rad/s) through
    Chipmunk's setters (which wake a sleeping body, as pymunk's do)."""
    for i in range(order.shape[0]):
        b = addrs[order[i]]
        _v_ivec(api[SET_V], b, vel[i, 0], vel[i, 1])
        _v_id(api[SET_W], b, vel[i, 2])


@njit(cache=True)
def space_loads(api: np.ndarray, space: int, dt: float) -> tuple[float, float, float]:
    """The space's gravity (m/s^2) and its damping factor over a step of ``dt`` (s), as Chipmunk's step takes
    them (``cpSpaceGetGravity``, ``cpSpaceGetDamping`` to the power dt); ``space``: the cpSpace's address."""
    gx, gy = _vec_i(api[SPACE_GRAVITY], space)
    return gx, gy, _d_i(api[SPACE_DAMPING], space) ** dt


@njit(cache=True)
def step_compiled(dt: float, api: np.ndarray, space: int, addrs: np.ndarray, lookup: np.ndarray, rec: np.ndarray,
                  raw: np.ndarray, body: np.ndarray, bodies: np.ndarray, shapes: np.ndarray, geo: np.ndarray,
                  tables: np.ndarray, tol: float, max_iter: int, max_sweeps: int, order: np.ndarray, vel: np.ndarray,
                  stopped: np.ndarray, report: np.ndarray, memo: np.ndarray) -> tuple[int, int, int, int, int]:
    """The compiled route's whole coupled step in one call: :func:`read_compiled`, then
    :func:`rrbody.contact.islands.couple_islands` into the caller's arrays with the space's gravity and
    damping (:func:`space_loads`; ``space``: the cpSpace's address), then :func:`write_compiled`. Returns
    couple_islands' counts, or (minus the records or points needed, 0, 0, 0, 0) where a buffer is too small
    (nothing written then)."""
    n_raw = read_compiled(api, addrs, lookup, rec, raw, body)
    if n_raw <= 0:
        return n_raw, 0, 0, 0, 0
    gx, gy, damp = space_loads(api, space, dt)
    counts = I.couple_islands(raw, n_raw, body, bodies, shapes, geo, tables, dt, damp, gx, gy, tol, max_iter,
                              max_sweeps, order, vel, stopped, report, memo)
    write_compiled(api, addrs, order[:counts[0]], vel)
    return counts


# ---- the public route ------------------------------------------------------------------------------
def read_public(space: Any, bodies: list[Any], slots: dict[Any, int], raw: np.ndarray, body: np.ndarray) -> int:
    """The public route's read (pymunk's Python API) of every contact of the plugin's ``bodies`` (by row;
    ``slots``: body -> row) in ``space`` into ``raw`` and ``body``, as :func:`read_compiled`. Returns the raw
    point rows written, or minus the rows needed."""
    import pymunk

    static, kinematic = pymunk.Body.STATIC, pymunk.Body.KINEMATIC
    body[:, I.RB_SEEN] = 0.0
    found: list[tuple] = []
    for x in bodies:
        # (read inside the call: pymunk hands each arbiter over with this body's shape first only there)
        x.each_arbiter(lambda arb, x=x: found.append((x, *arb.shapes, arb.contact_point_set, arb.friction,
                                                      arb.restitution, arb.surface_velocity)))
    if not found:
        return 0
    joined = {b for c in space.constraints for b in (c.a, c.b)}
    n_raw = 0
    for x, sa, sb, cps, friction, restitution, sv in found:
        jx = slots[x]
        other = sb.body
        jo = slots.get(other, -1)
        if 0 <= jo < jx:
            continue  # an arbiter of two plugin bodies: taken once, from the one with the lower row
        if sa.sensor or sb.sensor or not cps.points:
            continue
        if n_raw + len(cps.points) > raw.shape[0]:
            return -(n_raw + 2 * len(found))
        kind = I.KIND_PLANE
        if jo < 0:
            t = other.body_type
            kind = I.KIND_STATIC if t == static else I.KIND_KINEMATIC if t == kinematic else I.KIND_OFF
        for b, j in ((x, jx), (other, jo)):
            if j >= 0 and body[j, I.RB_SEEN] == 0.0:
                _public_state(b, body[j])
                body[j, I.RB_JOINT] = 1.0 if b in joined else 0.0
                body[j, I.RB_SEEN] = 1.0
        fixed = np.zeros(I.N_RB)
        if jo < 0:
            _public_state(other, fixed)
        for p in cps.points:
            raw[n_raw] = (jx, jo, kind, cps.normal.x, cps.normal.y, p.point_a.x, p.point_a.y, p.point_b.x, p.point_b.y,
                          friction, restitution, sv.x, sv.y, *((fixed[I.RB_VX], fixed[I.RB_VY], fixed[I.RB_SPIN],
                                                               fixed[I.RB_CGX], fixed[I.RB_CGY]) if jo < 0 else
                                                              (0.0, 0.0, 0.0, 0.0, 0.0)))
            n_raw += 1
    return n_raw


def _public_state(b: Any, out: np.ndarray) -> None:
    """As :func:`_body_state`, through pymunk's properties (the same arithmetic for the centre of gravity)."""
    p, c, a = b.position, b.center_of_gravity, b.angle
    ca, sa = math.cos(a), math.sin(a)
    v = b.velocity
    out[I.RB_CGX] = p.x + ca * c.x - sa * c.y
    out[I.RB_CGY] = p.y + sa * c.x + ca * c.y
    out[I.RB_ANGLE] = a
    out[I.RB_VX] = v.x
    out[I.RB_VY] = v.y
    out[I.RB_SPIN] = b.angular_velocity


def write_public(bodies: list[Any], order: np.ndarray, vel: np.ndarray) -> None:
    """:func:`write_compiled` through pymunk's setters."""
    for i, j in enumerate(order.tolist()):
        b = bodies[j]
        b.velocity = (vel[i, 0], vel[i, 1])
        b.angular_velocity = vel[i, 2]


# ---- the compiled route and its probe ---------------------------------------------------------------
class CompiledRoute:
    """The compiled route's address table (``api``: int64, the C functions of :data:`_API` and the three
    callbacks), made by :func:`compiled_route`."""

    def __init__(self, api: np.ndarray) -> None:
        self.api = api


def _addresses() -> np.ndarray | None:
    try:
        from pymunk._chipmunk import ffi, lib

        found = [int(ffi.cast("uintptr_t", ffi.addressof(lib, name))) for name in _API]
    except (ImportError, AttributeError, TypeError):
        return None
    return np.array([*found, _on_arbiter.address, _on_constraint.address, _on_any.address], dtype=np.int64)


_ROUTE: list[Any] = []


def compiled_route() -> CompiledRoute | None:
    """The compiled route, if this pymunk and platform give the public route's bits through it (probed once
    per process: :func:`_probe`); None where it is off (``RRBODY_NO_PRIVATE=1``, Windows, a machine other
    than x86-64 or ARM64, a pymunk without these functions, or a probe that reads other numbers)."""
    if not private_allowed():
        return None
    if not _ROUTE:
        ok = sys.platform != "win32" and platform.machine().lower() in ("x86_64", "amd64", "arm64", "aarch64")
        api = _addresses() if ok else None
        _ROUTE.append(CompiledRoute(api) if api is not None and _probe(api) else None)
    return _ROUTE[0]


def _probe(api: np.ndarray) -> bool:
    """Read a scene holding every kind of contact (two plugin bodies touching each other, a static wall, a
    kinematic body with friction, restitution and a surface velocity, a body off the plane, a sensor, a joint)
    through both routes, and write a velocity back: True if every number is the same bits."""
    import pymunk

    space = pymunk.Space()
    wall = pymunk.Segment(space.static_body, (-1.0, -0.3), (1.0, -0.3), 0.05)
    wall.friction, wall.elasticity = 0.25, 0.5
    space.add(wall)
    made = []
    for k, (x, y, a) in enumerate(((0.0, -0.205, 0.02), (0.18, -0.155, -0.2), (0.45, -0.205, 0.01))):
        b = pymunk.Body()
        s = pymunk.Poly.create_box(b, (0.2, 0.1)) if k != 1 else pymunk.Circle(b, 0.1, (0.01, -0.02))
        s.density, s.friction, s.elasticity = 10.0, 0.75, 0.25
        b.position, b.angle = (x, y), a
        b.velocity, b.angular_velocity = (0.1 * k - 0.2, -0.3), 0.5 - k
        space.add(b, s)
        made.append(b)
    off = pymunk.Body()  # a dynamic body off the plane, touching the first
    off_shape = pymunk.Circle(off, 0.05)
    off_shape.density = 5.0
    off.position = (-0.05, -0.11)
    space.add(off, off_shape)
    kin = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    ks = pymunk.Circle(kin, 0.08)
    ks.friction, ks.elasticity, ks.surface_velocity = 0.5, 0.2, (0.3, -0.1)
    kin.position, kin.velocity, kin.angular_velocity = (-0.15, -0.1), (0.4, -0.1), 2.0
    sensor = pymunk.Circle(space.static_body, 0.3, (0.0, -0.1))
    sensor.sensor = True
    space.add(kin, ks, sensor, pymunk.PivotJoint(made[2], space.static_body, (0.45, 0.0)))
    space.step(0.01)
    plugin = made[:2] + made[2:]  # rows 0, 1 (and 2: held by the joint)
    slots = {b: j for j, b in enumerate(plugin)}
    from rrbody.engine.memory.batchio import body_uid

    ids = np.array([body_uid(b) for b in plugin], dtype=np.int64)
    order = np.argsort(ids, kind="stable")
    lookup = np.ascontiguousarray(np.vstack([ids[order], order.astype(np.int64)]))
    addrs = np.array([address(b._body) for b in plugin], dtype=np.int64)
    out = []
    for route in ("public", "compiled"):
        raw = np.zeros((64, I.N_RP))
        body = np.zeros((len(plugin), I.N_RB))
        if route == "public":
            n = read_public(space, plugin, slots, raw, body)
        else:
            rec = np.zeros(4 + _REC * 32, dtype=np.int64)
            n = read_compiled(api, addrs, lookup, rec, raw, body)
        if n <= 0:
            return False
        keep = np.lexsort(raw[:n].T[::-1])
        out.append((raw[:n][keep], body))
    (r0, b0), (r1, b1) = out
    kinds = set(r0[:, I.RP_KIND].tolist())
    if not (r0.shape == r1.shape and np.array_equal(r0.view(np.int64), r1.view(np.int64))
            and np.array_equal(b0.view(np.int64), b1.view(np.int64))
            and {I.KIND_PLANE, I.KIND_STATIC, I.KIND_KINEMATIC, I.KIND_OFF} <= kinds):
        return False
    space.gravity, space.damping = (0.25, -9.75), 0.875
    gx, gy = space.gravity
    if space_loads(api, space_address(space), 0.01) != (gx, gy, space.damping ** 0.01):
        return False
    write_compiled(api, addrs, np.array([1], dtype=np.int64), np.array([[0.125, -0.375, 1.5]]))
    return (made[1].velocity.x, made[1].velocity.y, made[1].angular_velocity) == (0.125, -0.375, 1.5)


def space_address(space: Any) -> int:
    """The address of a pymunk space's cpSpace (for :func:`step_compiled`)."""
    return address(space._space)
