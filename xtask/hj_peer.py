"""The game of two cars' time to capture by hj_reachability (WENO5 in space, TVD-RK3 in time),
beside ours: `cargo xtask hj --compare` runs this with our solution in a file and prints both
solvers' figures on the same grid (time, memory, tail chase, agreement where V is smooth, the
width of V's jumps, and how far V falls below r - eps, the least time to close on an evader
that stands still).

The reduced game is hji's (hji/src/lib.rs): the evader at (x, y) in the pursuer's frame with
relative heading phi, lengths in r_p and times in r_p / v_pm; the pursuer turns at u in [-1, 1],
the evader runs at a speed s in [0, a] turning at w with |w| <= w_e s / a (a triangle of
controls whose corners are the two full turns and the stop). Capture is the disc of radius
eps. The peer solves the backward reachable tube of that disc from the signed distance to it,
and the time to capture is the first time the tube holds the node (linear between the
snapshots). As in ours, leaving the box is never captured: the box's outermost ring of nodes is
an obstacle the tube does not enter (hj_reachability's static obstacle; without it the peer
extrapolates V beyond the box and captures states that ours, leaving the box, does not).
"""

import argparse
import json
import resource
import sys
import time

import numpy as np

import jax
import jax.numpy as jnp
import hj_reachability as hj
from flax import struct

# Per-cell change of V (r_p / v_pm) that marks a jump, and below which V counts as smooth.
JUMP = 1.0
# A ray across a barrier spans this many cells either side of its jump, and counts where V
# moves by at least BARRIER between its ends in both solutions.
HALF_RAY = 4
BARRIER = 2.0
TAIL_CHASE = [1.0, 2.0, 3.0, 4.0]


@struct.dataclass
class Triangle(hj.sets.BoundedSet):
    """The evader's (speed, turn rate) controls: the hull of (a, -w), (a, w) and (0, 0)."""

    corners: jnp.ndarray

    def extreme_point(self, direction):
        return self.corners[jnp.argmax(self.corners @ direction)]

    @property
    def bounding_box(self):
        return hj.sets.Box(jnp.min(self.corners, axis=0), jnp.max(self.corners, axis=0))


class TwoCars(hj.ControlAndDisturbanceAffineDynamics):
    """x' = s cos(phi) - 1 + u y, y' = s sin(phi) - u x, phi' = w - u."""

    def __init__(self, a, w_e):
        corners = jnp.array([[a, -w_e], [a, w_e], [0.0, 0.0]])
        super().__init__("min", "max", hj.sets.Box(jnp.array([-1.0]), jnp.array([1.0])),
                         Triangle(corners))

    def open_loop_dynamics(self, state, time):
        return jnp.array([-1.0, 0.0, 0.0])

    def control_jacobian(self, state, time):
        x, y, _ = state
        return jnp.array([[y], [-x], [-1.0]])

    def disturbance_jacobian(self, state, time):
        phi = state[2]
        return jnp.array([[jnp.cos(phi), 0.0], [jnp.sin(phi), 0.0], [0.0, 1.0]])


def solve_peer(args):
    """The peer's time to capture on the grid (x, y, phi), inf where not within the horizon."""
    half = args.half
    grid = hj.Grid.from_lattice_parameters_and_boundary_conditions(
        hj.sets.Box(np.array([-half, -half, -np.pi]), np.array([half, half, np.pi])),
        (args.nodes, args.nodes, args.headings),
        periodic_dims=2,
    )
    x, y = grid.states[..., 0], grid.states[..., 1]
    values = jnp.sqrt(x * x + y * y) - args.eps
    # Positive in the outermost ring (within a cell of the box's edge), negative inside.
    h = 2.0 * half / (args.nodes - 1)
    edge = jnp.maximum(jnp.abs(x), jnp.abs(y))
    obstacle = edge - (half - h) - 0.5 * h
    settings = hj.SolverSettings.with_accuracy(
        "very_high", hamiltonian_postprocessor=hj.solver.backwards_reachable_tube,
        value_postprocessor=hj.solver.static_obstacle(obstacle) if args.box_exits == "never"
        else hj.solver.identity)
    dynamics = TwoCars(args.speed_ratio, args.evader_turn)
    reach = np.where(np.asarray(values) <= 0.0, 0.0, np.inf)
    before = np.asarray(values)
    t = 0.0
    while t < args.horizon - 1e-9:
        step = min(args.out_dt, args.horizon - t)
        values = hj.step(settings, dynamics, grid, -t, values, -(t + step), progress_bar=False)
        now = np.asarray(values)
        entered = np.isinf(reach) & (now <= 0.0)
        share = before / np.maximum(before - now, 1e-12)
        reach = np.where(entered, t + step * np.clip(share, 0.0, 1.0), reach)
        before, t = now, t + step
    return reach


def tail_chase(v, args):
    """V at the evader dead ahead with the pursuer's heading, d r_p away, less the exact value."""
    h = 2.0 * args.half / (args.nodes - 1)
    j, k = args.nodes // 2, args.headings // 2
    errors = []
    for d in TAIL_CHASE:
        f = (d + args.half) / h
        i = int(np.floor(f))
        got = v[i, j, k] + (f - i) * (v[i + 1, j, k] - v[i, j, k])
        errors.append(got - (d - args.eps) / (1.0 - args.speed_ratio))
    return errors


def cell_jumps(v):
    """The largest change of V to a neighbour on each axis (periodic in phi), per node."""
    most = np.zeros_like(v)
    for axis in range(3):
        if axis == 2:
            ahead = np.abs(np.roll(v, -1, axis) - v)
            most = np.maximum(most, np.maximum(ahead, np.roll(ahead, 1, axis)))
        else:
            d = np.abs(np.diff(v, axis=axis))
            pad = [(0, 0)] * 3
            pad[axis] = (0, 1)
            ahead = np.pad(d, pad)
            pad[axis] = (1, 0)
            most = np.maximum(most, np.maximum(ahead, np.pad(d, pad)))
    return np.nan_to_num(most, nan=np.inf, posinf=np.inf)


def smooth_nodes(v, outside):
    """Nodes outside the disc whose V changes by less than JUMP per cell within two cells."""
    calm = cell_jumps(v) < JUMP
    near = calm.copy()
    for axis in range(3):
        for shift in (-2, -1, 1, 2):
            near &= np.roll(calm, shift, axis)
    return near & outside & np.isfinite(v)


def rise(profile):
    """Cells over which `profile` (one ray) moves from 10 % to 90 % of its ends' difference."""
    lo, hi = profile[0], profile[-1]
    span = hi - lo

    def first(level):
        for n in range(len(profile) - 1):
            a, b = profile[n] - level, profile[n + 1] - level
            if a * np.sign(span) <= 0.0 < b * np.sign(span):
                return n + (-a) / (b - a) if b != a else float(n)
        return float(len(profile) - 1)

    return abs(first(lo + 0.9 * span) - first(lo + 0.1 * span))


def barrier_widths(ours, peer):
    """Both solutions' 10-90 % rise, in cells, on rays along x and y centred on a cell where
    either jumps by JUMP or more, the largest jump on its ray, and whose ends differ by
    BARRIER or more in both."""
    n = ours.shape[0]
    rays = set()
    for axis in (0, 1):
        for v in (ours, peer):
            d = np.nan_to_num(np.abs(np.diff(v, axis=axis)), nan=0.0, posinf=0.0)
            for idx in zip(*np.nonzero(d >= JUMP)):
                start = idx[axis] - HALF_RAY + 1
                if start < 0 or start + 2 * HALF_RAY > n - 1:
                    continue
                ray = ray_indices(idx, axis, start)
                if np.argmax(np.abs(np.diff(v[ray]))) == HALF_RAY - 1:
                    rays.add((axis, tuple(int(i) for i in idx[:axis] + (start,) + idx[axis + 1:])))
    widths = ([], [])
    for axis, idx in sorted(rays):
        ray = ray_indices(idx, axis, idx[axis])
        profiles = (ours[ray], peer[ray])
        if all(np.all(np.isfinite(p)) and abs(p[-1] - p[0]) >= BARRIER for p in profiles):
            for w, p in zip(widths, profiles):
                w.append(rise(p))
    return widths


def ray_indices(idx, axis, start):
    """The 2 HALF_RAY + 1 nodes from `start` along `axis` through node `idx`, as an index."""
    columns = [np.full(2 * HALF_RAY + 1, i) for i in idx]
    columns[axis] = np.arange(start, start + 2 * HALF_RAY + 1)
    return tuple(columns)


def below_stop(v, r, eps):
    """How far V falls below r - eps, the least time to close on an evader that stands still
    (which it always may), over nodes outside the disc captured within the horizon: the least
    V - (r - eps), and the share of nodes below it by more than a thousandth."""
    reached = np.isfinite(v) & (r > eps + 1e-9)
    gap = (v - (r - eps))[reached]
    return float(gap.min()), float((gap < -1e-3).mean())


def main():
    p = argparse.ArgumentParser()
    for name in ("nodes", "headings"):
        p.add_argument(f"--{name}", type=int, required=True)
    for name in ("half", "eps", "speed-ratio", "evader-turn", "horizon", "ours-seconds",
                 "ours-peak-mb"):
        p.add_argument(f"--{name}", type=float, required=True)
    p.add_argument("--out-dt", type=float, default=0.05)
    p.add_argument("--box-exits", choices=["never", "extrapolate"], default="never")
    p.add_argument("--ours", required=True)
    p.add_argument("--peer-out", required=True)
    args = p.parse_args()
    n, k = args.nodes, args.headings
    ours = np.fromfile(args.ours, dtype="<f8").reshape(k, n, n).transpose(2, 1, 0).copy()
    ours[ours > args.horizon] = np.inf

    started = time.perf_counter()
    peer = solve_peer(args)
    peer_seconds = time.perf_counter() - started
    peer_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    # Beside ours, in its layout (phi slowest, x fastest; inf where not captured), for a look.
    peer.transpose(2, 1, 0).astype("<f8").tofile(args.peer_out)

    axis = np.linspace(-args.half, args.half, n)
    x, y = np.meshgrid(axis, axis, indexing="ij")
    r = np.broadcast_to(np.hypot(x, y)[..., None], ours.shape)
    h = axis[1] - axis[0]
    outside = np.broadcast_to((np.hypot(x, y) > args.eps + h)[..., None], ours.shape)
    smooth = smooth_nodes(ours, outside) & smooth_nodes(peer, outside)
    gap = np.abs(ours - peer)[smooth]
    widths = barrier_widths(ours, peer)
    both = np.isfinite(ours) & np.isfinite(peer) & outside
    report = {
        "grid": f"{n} x {n} x {k}",
        "jax": jax.__version__,
        "ours": {"seconds": args.ours_seconds, "peak_mb": args.ours_peak_mb,
                 "tail_chase": tail_chase(ours, args), "below_stop": below_stop(ours, r, args.eps)},
        "peer": {"seconds": peer_seconds, "peak_mb": peer_mb, "tail_chase": tail_chase(peer, args),
                 "below_stop": below_stop(peer, r, args.eps)},
        "smooth_nodes": int(smooth.sum()),
        "smooth_median": float(np.median(gap)) if gap.size else None,
        "smooth_p90": float(np.quantile(gap, 0.9)) if gap.size else None,
        "reached_only_ours": int((np.isfinite(ours) & ~np.isfinite(peer) & outside).sum()),
        "reached_only_peer": int((~np.isfinite(ours) & np.isfinite(peer) & outside).sum()),
        "reached_both": int(both.sum()),
        "rays": len(widths[0]),
        "width_p50": [float(np.quantile(w, 0.5)) if w else None for w in widths],
        "width_p90": [float(np.quantile(w, 0.9)) if w else None for w in widths],
    }
    json.dump(report, sys.stdout)
    print()


if __name__ == "__main__":
    main()
