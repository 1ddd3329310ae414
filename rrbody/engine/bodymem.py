"""Raw reads of pymunk's C structs in compiled code: an object's address, and the float64 or int64
at a byte address (the recorder's capture, :mod:`rrbody.engine.capture`, which finds where a body's
state lies in pymunk's ``cpBody`` and checks it before it reads anything this way).

The addresses must be those of objects the caller keeps alive (the recorder holds its bodies), so
a read never touches freed memory.
"""

from __future__ import annotations

from typing import Any

from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic

__all__ = ["address", "f64_at", "i64_at"]


def address(cdata: Any) -> int:
    """The address of a pymunk C object (``body._body``, ``space._space``) as an int64."""
    from pymunk._chipmunk import ffi

    a = int(ffi.cast("uintptr_t", cdata))
    return a - (1 << 64) if a >= 1 << 63 else a


@intrinsic
def f64_at(typingctx: Any, addr: Any) -> Any:
    """The float64 at byte address ``addr`` (an int64)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.load(builder.inttoptr(args[0], ir.PointerType(ir.DoubleType())))
    return types.float64(types.int64), codegen


@intrinsic
def i64_at(typingctx: Any, addr: Any) -> Any:
    """The int64 at byte address ``addr`` (an int64)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.load(builder.inttoptr(args[0], ir.PointerType(ir.IntType(64))))
    return types.int64(types.int64), codegen
