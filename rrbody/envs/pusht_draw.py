"""Push-T's pictures drawn with numpy alone (no pygame, no OpenCV), exactly as gym-pusht 0.1.8 draws them.

gym-pusht paints a 512 x 512 pygame surface (1 workspace unit = 1 pixel; row = y, column = x, y down),
then resizes it with ``cv2.resize`` (bilinear). Here each primitive of that surface is rasterised by
pygame 2.6's own rule (scanline polygons, midpoint circles, clipped Bresenham lines of width 4,
antialiased lines) on vertices rounded as pymunk's ``to_pygame`` rounds them, and mixed with OpenCV's
fixed-point weights. Only the surface pixels the resize reads are painted, as labels (192 x 192 of
them for 96 x 96); a picture pixel whose four source pixels share a label is that label's colour.
What is drawn, and how well it agrees with gym-pusht: docs/envs-pictures.md.
"""
from __future__ import annotations

import functools
from typing import Any, NamedTuple

import numpy as np

SIZE = 512  #: the workspace's side, units (= the pixels of gym-pusht's surface)
AGENT_RADIUS = 15  #: units
MAX_SIDE = 4096  #: the largest picture side accepted, pixels
MAX_COORD = 1.0e4  #: the largest coordinate magnitude accepted, units (far outside the workspace)
#: Colours (RGB) by label: background, goal (LightGreen), block fill (pymunk_override's light_color of
#: LightSlateGray: 1.2x in float32, cut) and outline, agent (RoyalBlue) and its light_color, walls (LightGray).
PALETTE = np.array([(255, 255, 255), (144, 238, 144), (143, 163, 184), (119, 136, 153), (65, 105, 225),
                    (78, 126, 255), (211, 211, 211)], dtype=np.uint8)
CONTACT_COLOUR = np.array((231, 76, 60), dtype=np.float32)  # pymunk's collision_point_color
#: The walls' end points (gym-pusht's segments of radius 2), units.
WALLS = np.array([[(5, 506), (5, 5)], [(5, 5), (506, 5)], [(506, 5), (506, 506)], [(5, 506), (506, 506)]])

_PREVIOUS, _NEXT = [3, 0, 1, 2], [1, 2, 3, 0]
_BLOCK_LAYERS = np.array([1, 1, 1, 1, 3, 3, 3, 3, 0, 2])  # the 8 edges, 2 fills: 0, 2 bar, stem fill; 1, 3 outline
_OFF = 1 << 40  # a span's first column where it has none (its last: _OFF - 1), past every column
#: Spans in a window of the grid (the pixels read) from grid row i0, column j0: by primitive and window row
#: the first and last surface column (first > last: none), ids; the same by window column, in rows, ids.
Spans = tuple[Any, Any, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]


class _Tables(NamedTuple):
    """How a picture size reads the surface: its rows and columns; their grid index at index[0 or 1, r + 1]
    (-1: not read); per picture pixel, the grid's flat indices of its source pixels (y0 x0, y0 x1, y1 x0,
    y1 x1), OpenCV's weights (x: a0 a1 a0 a1, y: b0 b1; /2048); the walls' cells; the last grids painted."""
    rows: np.ndarray
    cols: np.ndarray
    index: np.ndarray
    corners: np.ndarray
    weights: np.ndarray
    walls: np.ndarray
    last: dict[str, tuple[bytes, np.ndarray]]


@functools.cache
def _circle_widths(r: int) -> np.ndarray:
    """Half-widths w of pygame's filled circle of radius ``r`` by row offset k = -r .. r-1 (index k + r):
    the row's pixels run from x0 - w to x0 + w - 1 (the disk is centred on the pixel corner x0, y0)."""
    w, x, y, f = np.zeros(2 * r, dtype=np.int64), 0, r, 1 - r  # the midpoint walk of an octant
    while x < y:
        if f >= 0:
            y, f = y - 1, f - 2 * (y - 1)
        x, f = x + 1, f + 2 * x + 3
        # pygame writes the rows of the octant's x only where y is about to step
        for row, half in ((x - 1, y), (-x, y)) + (((y - 1, x), (-y, x)) if f >= 0 else ()):
            w[row + r] = max(w[row + r], half)
    w.setflags(write=False)
    return w


def _quads(p: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``pygame.draw.polygon`` of convex integer quadrilaterals ``p`` (q, 4, 2) on the surface ``rows``: the
    first and last column (q, rows). pygame crosses the row with each edge (its lower end excluded but on
    the last row) and truncates; a convex polygon's crossings pair up as the least and the greatest."""
    x, y = p[..., 0].T[..., None].astype(np.float64), p[..., 1].T[..., None].astype(np.float64)  # (4, q, 1)
    xp, yp = x[_PREVIOUS], y[_PREVIOUS]  # each edge runs from the previous vertex
    up, bottom = yp < y, y.max(axis=0)
    y1, y2, x1, x2 = np.minimum(yp, y), np.maximum(yp, y), np.where(up, xp, x), np.where(up, x, xp)
    hit = ((dy := y2 - y1) != 0) & (((rows >= y1) & (rows < y2)) | ((rows == bottom) & (y2 == bottom)))  # (4, q, rows)
    xs = np.trunc((rows - y1) * (x2 - x1) / np.where(dy != 0, dy, 1) + x1)  # as pygame rounds: (int)
    first = np.where(hit, xs, _OFF).min(axis=0).astype(np.int64)
    return first, np.maximum(np.where(hit, xs, -1.0).max(axis=0).astype(np.int64), first - 1)


def _lines(p1: np.ndarray, p2: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> list[np.ndarray]:
    """``pygame.draw.line`` of width 4 from ``p1`` to ``p2`` (n, 2, integer), a Bresenham walk along the major
    axis (y where |dx| <= |dy|: "steep") drawing a run of 4 pixels (minor offsets -1..2) per step: on the
    ``rows``, the steep lines' runs (first, last column; (n, rows)), on the ``cols`` the others' (rows).
    pygame clips the line to the surface (Liang-Barsky on 0..512, ends rounded half away from 0) but walks
    from the clipped start with the whole line's steps, past the clipped end to the line's end or edge."""
    ad = np.abs(d := p2 - p1)
    steep, big, small = ad[:, 0] <= ad[:, 1], ad.max(axis=1, initial=0)[:, None], ad.min(axis=1, initial=1 << 30)[:,
                                                                                                                  None]
    sgn, c1, end = np.where(d > 0, 1, -1), p1, big
    if min(p1.min(initial=0), p2.min(initial=0)) < 0 or max(p1.max(initial=0), p2.max(initial=0)) > SIZE:
        n, mj = np.arange(len(p1)), steep.astype(np.int64)
        flat, dd = d == 0, np.where(d == 0, 1, d)
        ta, tb = -p1 / dd, (SIZE - p1) / dd
        lo = np.max(np.where(flat, 0.0, np.minimum(ta, tb)), axis=1, initial=0.0)
        hi = np.min(np.where(flat, 1.0, np.maximum(ta, tb)), axis=1, initial=1.0)
        shown = (lo <= hi) & ~np.any(flat & ((p1 < 0) | (p1 > SIZE)), axis=1)
        c1, c2 = (p1 + np.trunc(d * t[:, None] + np.copysign(0.5, d * t[:, None])).astype(np.int64) for t in (lo, hi))
        k = np.arange(int(big.max(initial=0)) + 1 + 2 * SIZE)  # walk it all to find where the walk stops
        s_mj, s_mn = sgn[n, mj][:, None], sgn[n, 1 - mj][:, None]
        along = c1[n, mj][:, None] + s_mj * k
        across = c1[n, 1 - mj][:, None] + s_mn * -((big // 2 - k * small) // np.maximum(big, 1))
        reached = ((along - c2[n, mj][:, None]) * s_mj >= 0) & ((across - c2[n, 1 - mj][:, None]) * s_mn >= 0)
        inside = (along >= 0) & (along < SIZE) & (across >= -2) & (across <= SIZE)  # either end of the run
        stop = (k >= np.argmax(reached, axis=1)[:, None]) & ((along == p2[n, mj][:, None]) | ~inside)
        end = np.where(shown, np.argmax(stop | (k == k[-1]), axis=1), -1)[:, None]
    out = []
    for m, axis, drawn in ((rows, 1, steep), (cols, 0, ~steep)):  # the steps at major coordinates m
        k = (m - c1[:, axis, None]) * sgn[:, axis, None]
        # the walk's minor steps: ceil((k small - big // 2) / big)
        minor = c1[:, 1 - axis, None] + sgn[:, 1 - axis, None] * -((big // 2 - k * small) // np.maximum(big, 1))
        ok = drawn[:, None] & (k >= 0) & (k <= end)
        out += [np.where(ok, minor - 1, _OFF), np.where(ok, minor + 2, _OFF - 1)]
    return out


def _fat(a: np.ndarray, b: np.ndarray, fills: np.ndarray, t: _Tables) -> Spans:
    """Spans of pymunk_override's draw_fat_segment (radius 2) from ``a`` to ``b`` (n, 2, units): a line of
    width 4, a quadrilateral offset by the rounded (|dy|, |dx|) scaled to 2 (perpendicular only where dx
    and dy differ in sign), disks at both ends (primitive i); the fills ``fills`` (q, 4, 2; n + j)."""
    p1, p2 = (np.rint(e).astype(np.int64) for e in (a, b))  # to_pygame: round half to even
    o = np.abs(p2 - p1)[:, ::-1].astype(np.float64)  # pymunk_override's "orthog", scaled below
    length = np.sqrt(o[:, 0] ** 2 + o[:, 1] ** 2)
    n = np.flatnonzero(length > 0)  # a segment of length 0 gets its line only
    o = np.rint(o[n] * (2.0 / length[n])[:, None]).astype(np.int64)
    quads = np.concatenate([np.stack([p1[n] - o, p1[n] + o, p2[n] + o, p2[n] - o], axis=1), fills])
    ends, pts = np.concatenate([p1[n], p2[n]]), np.concatenate([quads.reshape(-1, 2), p1, p2])
    lo, hi = pts.min(axis=0, initial=SIZE) - 2, pts.max(axis=0, initial=0) + 3
    if pts.size and (pts.min() < 0 or pts.max() > SIZE):  # a clipped line may run on to the edge
        lo, hi = (0, 0), (SIZE, SIZE)
    (i0, i1), (j0, j1) = np.searchsorted(t.rows, (lo[1], hi[1])), np.searchsorted(t.cols, (lo[0], hi[0]))
    rows, cols = t.rows[i0:i1], t.cols[j0:j1]
    first, last = _quads(quads, rows)
    k = rows - ends[:, 1:] + 2  # the disks' rows, from their top
    w, on = _circle_widths(2)[np.clip(k, 0, 3)], (k >= 0) & (k < 4)
    lf, ll, cf, cl = _lines(p1, p2, rows, cols)
    first = np.concatenate([first, np.where(on, ends[:, :1] - w, _OFF), lf])
    last = np.concatenate([last, np.where(on, ends[:, :1] + w - 1, _OFF - 1), ll])
    ids = np.concatenate([n, len(a) + np.arange(len(fills)), n, n, np.arange(len(a))])
    return i0, j0, first, last, ids, cf, cl, np.arange(len(a))


def _paint(grid: np.ndarray, t: _Tables, s: Spans, labels: list[int]) -> None:
    """Paint spans ``s`` into ``grid`` (labels of the pixels read), those of primitive i with
    ``labels[i]``, in turn (later over earlier, as pygame paints)."""
    i0, j0, hf, hl, hid, vf, vl, vid = s
    m, h, w = len(labels), hf.shape[1], vf.shape[1]
    # a span covers window columns (rows) a..b-1; one on no pixel read has a == b <= w (h)
    ca, cb = (np.minimum(np.searchsorted(t.cols, e, side=sd) - j0, w) for e, sd in ((hf, "left"), (hl, "right")))
    # coverage by difference arrays: +1 where a span starts, -1 past its end, summed along it
    at, size = (hid[:, None] * h + np.arange(h)) * (w + 1), m * h * (w + 1)
    d = np.bincount((at + ca).ravel(), minlength=size) - np.bincount((at + cb).ravel(), minlength=size)
    inside = d.reshape(m, h, w + 1).cumsum(axis=2)[..., :-1] > 0
    if len(vid):
        ra, rb = (np.minimum(np.searchsorted(t.rows, e, side=sd) - i0, h) * w for e, sd in ((vf, "left"), (vl,
                                                                                                           "right")))
        at, size = vid[:, None] * (h + 1) * w + np.arange(w), m * (h + 1) * w
        d = np.bincount((at + ra).ravel(), minlength=size) - np.bincount((at + rb).ravel(), minlength=size)
        inside |= d.reshape(m, h + 1, w).cumsum(axis=1)[:, :-1] > 0
    window = grid[i0:i0 + h, j0:j0 + w]
    for i, label in enumerate(labels):
        window[inside[i]] = label


def _disk(grid: np.ndarray, t: _Tables, c: np.ndarray, r: int, label: int) -> None:
    """Paint pygame's filled circle of radius ``r`` at the integer centre ``c`` into ``grid``."""
    (r0, r1), (c0, c1) = np.searchsorted(t.rows, (c[1] - r, c[1] + r)), np.searchsorted(t.cols, (c[0] - r, c[0] + r))
    w, x = _circle_widths(r)[t.rows[r0:r1] - c[1] + r][:, None], t.cols[c0:c1] - c[0]
    grid[r0:r1, c0:c1][(x >= -w) & (x < w)] = label


def _axis(n: int, across: bool) -> tuple[np.ndarray, np.ndarray]:
    """cv2.resize's INTER_LINEAR sampling of the 512 surface pixels for ``n`` picture pixels: source
    pixel (d + 0.5) * scale - 0.5 in float32, weights rounded to 1/2048. Past an edge OpenCV clamps
    the pixels, and along a row (``across``) also zeroes the fraction; down a column it keeps it."""
    f = ((np.arange(n) + 0.5) * (1.0 / (n / SIZE)) - 0.5).astype(np.float32)  # cv2 inverts n / 512
    f, s = f - np.floor(f), np.floor(f).astype(np.int64)
    f[across & ((s < 0) | (s >= SIZE - 1))] = 0
    w = np.rint(np.stack([np.float32(1) - f, f], axis=1) * np.float32(2048)).astype(np.int32)
    return np.clip(np.stack([s, s + 1], axis=1), 0, SIZE - 1), w


@functools.lru_cache(maxsize=4)
def _tables(width: int, height: int) -> _Tables:
    """How a ``width`` x ``height`` picture reads the surface (kept: an environment uses one or two sizes)."""
    (xs, xw), (ys, yw) = _axis(width, True), _axis(height, False)
    rows, cols = np.unique(ys), np.unique(xs)
    index = np.full((2, SIZE + 2), -1)
    index[0, rows + 1], index[1, cols + 1] = np.arange(len(rows)), np.arange(len(cols))
    yi, xi = index[0, ys + 1] * len(cols), index[1, xs + 1]
    corners = np.stack([yi[:, None, a] + xi[None, :, b] for a in (0, 1) for b in (0, 1)])
    weights = np.stack(np.broadcast_arrays(*(xw[None, :, k] for k in (0, 1, 0, 1)), yw[:, :1], yw[:, 1:]))
    t = _Tables(rows, cols, index, corners, weights.astype(np.int32), np.zeros(0, np.int64), {})
    grid = np.zeros((len(rows), len(cols)), dtype=np.uint8)
    _paint(grid, t, _fat(WALLS[:, 0], WALLS[:, 1], np.zeros((0, 4, 2), np.int64), t), [1] * len(WALLS))
    t = t._replace(walls=np.flatnonzero(grid))
    for a in t[:6]:
        a.setflags(write=False)
    return t


def _aaline(p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pixels (x, y) and float32 brightnesses of ``pygame.draw.aaline`` between integer points ``p``, ``q``:
    the end pixels at full brightness; between them the pixel pair astride the line, shared."""
    (x0, y0), (x1, y1) = p, q
    if x0 == x1 and y0 == y1:
        return np.array([x0]), np.array([y0]), np.ones(1, dtype=np.float32)
    steep = abs(x1 - x0) < abs(y1 - y0)  # walk along the major axis, from its smaller end
    (x0, y0), (x1, y1) = sorted(((y0, x0), (y1, x1)) if steep else ((x0, y0), (x1, y1)))
    g = np.float32(y1 - y0) / np.float32(x1 - x0)
    # pygame adds the gradient up in float32, one pixel lower (y + 1), from the first end
    v = np.cumsum(np.concatenate([[np.float32(y0 + 1)], np.full(x1 - x0 - 1, g)]), dtype=np.float32)[1:]
    b = (np.float32(1) - v) + (vi := v.astype(np.int64)).astype(np.float32)
    u, part = np.arange(x0 + 1, x1), vi < v
    u, v = np.concatenate([[x0, x1], u, u[part]]), np.concatenate([[y0, y1], vi - 1, vi[part]])
    b = np.concatenate([np.ones(2, dtype=np.float32), b, np.float32(1) - b[part]])
    return (v, u, b) if steep else (u, v, b)


def _marker(img: np.ndarray, x: int, y: int, size: int, thickness: int) -> None:
    """cv2.drawMarker's MARKER_CROSS at pixel (x, y): arms of half-length size // 2; thicker than 1, each
    arm is (thickness + 1) // 2 pixels to either side, with round caps of that radius."""
    m, r = size // 2, (thickness + 1) // 2 if thickness > 1 else 0
    y0, y1, x0, x1 = max(y - m - r, 0), min(y + m + r + 1, img.shape[0]), max(x - m - r, 0), min(x + m + r + 1,
                                                                                                 img.shape[1])
    dy, dx = np.arange(y0, y1)[:, None] - y, np.arange(x0, x1)[None, :] - x
    on = (((ay := np.abs(dy)) <= r) & ((ax := np.abs(dx)) <= m)) | ((ax <= r) & (ay <= m))
    if r:
        on |= ((ax - m) ** 2 + dy ** 2 <= r * r) | ((ay - m) ** 2 + dx ** 2 <= r * r)
    img[y0:y1, x0:x1][on] = (255, 0, 0)  # gym-pusht's colour


def _array(name: str, value: Any, shape: tuple[int, ...]) -> np.ndarray:
    """``value`` as float64 of ``shape`` (-1: any length), finite and within MAX_COORD, else ValueError."""
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers of shape {shape}, got {value!r}") from None
    if a.ndim != len(shape) or any(s not in (-1, k) for s, k in zip(shape, a.shape)):
        raise ValueError(f"{name} must have shape {shape} (-1: any length), got {a.shape}")
    if not np.all(np.abs(a) <= MAX_COORD):
        raise ValueError(f"{name} must be finite workspace coordinates within +-{MAX_COORD:g} units, got {a}")
    return a


def draw(agent: tuple[float, float], block: np.ndarray, goal: np.ndarray, width: int, height: int,
         action: np.ndarray | None = None, contacts: np.ndarray | None = None) -> np.ndarray:
    """The Push-T picture gym-pusht 0.1.8 draws, as uint8 RGB of shape (height, width, 3), C-contiguous.

    Frame: the workspace, units 0..512, x right, y down; picture pixel (i, j) shows the workspace point
    ((j + 0.5) * 512 / width - 0.5, (i + 0.5) * 512 / height - 0.5). agent: the disk's centre, units.
    block, goal: (2, 4, 2) world vertices of the T's bar, then stem (gym-pusht's ``_block_shapes``, each in
    pymunk's vertex order), units; drawn in that order, as gym-pusht does. width, height: 1..4096. action:
    the last action (x, y), units, or None: given, the red cross of gym-pusht's ``render()`` at column
    int(x / 512 * height), row int(y / 512 * width) (its order), arms 8/96 and thickness 1/96 of
    min(width, height) (at least 1 where gym-pusht fails). contacts: (n, 2, 2) segments, units, or
    None: per contact point of the last physics step (``arbiter.contact_point_set``), (point_a - 2
    normal, point_b + 2 normal), the marks pymunk's debug draw adds to gym-pusht's pictures.
    """
    for name, side in (("width", width), ("height", height)):
        if isinstance(side, bool) or not isinstance(side, (int, np.integer)) or not 1 <= side <= MAX_SIDE:
            raise ValueError(f"{name} must be an integer from 1 to {MAX_SIDE} (pixels), got {side!r}")
    a = np.rint(_array("agent", agent, (2,))).astype(np.int64)
    block = np.rint(_array("block", block, (2, 4, 2))).astype(np.int64)
    goal = np.rint(_array("goal", goal, (2, 4, 2))).astype(np.int64)
    t = _tables(int(width), int(height))
    # the goal rarely moves, and the block stays put while the agent is away: keep the last grids painted
    if (last := t.last.get("goal", (b"",)))[0] != (key := goal.tobytes()):
        last = t.last["goal"] = key, np.zeros((len(t.rows), len(t.cols)), np.uint8)
        _paint(last[1], t, _fat(*np.zeros((2, 0, 2)), goal, t), [1, 1])
    if (kept := t.last.get("block", (b"",)))[0] != (key := key + block.tobytes()):
        kept = t.last["block"] = key, last[1].copy()
        s = _fat(block.reshape(8, 2), block[:, _NEXT].reshape(8, 2), block, t)  # in layers, painted in turn
        _paint(kept[1], t, s[:4] + (_BLOCK_LAYERS[s[4]],) + s[5:7] + (_BLOCK_LAYERS[s[7]],), [2, 3, 2, 3])
    grid = kept[1].copy()
    for radius, label in ((AGENT_RADIUS, 4), (AGENT_RADIUS - 4, 5)):  # pymunk_override's lighter inner disk
        _disk(grid, t, a, radius, label)
    grid.flat[t.walls] = 6
    palette = PALETTE
    if contacts is not None:  # a blended pixel becomes a label of its own
        grid, colours = grid.astype(np.int32), [PALETTE]
        for p, q in np.rint(_array("contacts", contacts, (-1, 2, 2))).astype(np.int64):
            x, y, b = _aaline(p, q)
            ri, ci = t.index[0, np.clip(y, -1, SIZE) + 1], t.index[1, np.clip(x, -1, SIZE) + 1]
            read = (ri >= 0) & (ci >= 0)
            under, b = np.concatenate(colours)[grid[ri[read], ci[read]]].astype(np.float32), b[read, None]
            grid[ri[read], ci[read]] = sum(map(len, colours)) + np.arange(read.sum())
            colours.append((b * CONTACT_COLOUR + (np.float32(1) - b) * under).astype(np.uint8))
        palette = np.concatenate(colours)
    lab = grid.ravel().take(t.corners)
    img = palette.take(lab[0], axis=0)
    # a pixel whose four source pixels share a label is its colour (the weights sum to 2048 at any size)
    mixed = np.flatnonzero((lab[0] != lab[1]) | (lab[0] != lab[2]) | (lab[0] != lab[3]))
    if len(mixed):  # OpenCV's fixed point: along the rows /2048, then down as its SIMD path rounds
        w = t.weights.reshape(6, -1)[:, mixed, None]
        c = palette.astype(np.int32).take(lab.reshape(4, -1)[:, mixed], axis=0) * w[:4]
        c = (((c[0::2] + c[1::2]) >> 4) * w[4:]) >> 16
        img.reshape(-1, 3)[mixed] = (c[0] + c[1] + 2) >> 2
    if action is not None:
        x, y = (_array("action", action, (2,)) / SIZE * (height, width)).astype(np.int32)
        _marker(img, int(x), int(y), int(8 / 96 * (side := min(width, height))), max(int(1 / 96 * side), 1))
    return img
