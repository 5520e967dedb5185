"""Small 3D structures with closed-form collapse multipliers, built directly as Structure3D."""
import numpy as np

from lamodel.structure3d import Structure3D, tangent_frame


def box_vertices(lo, hi):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    v = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], float)
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    return v, faces


def box_on_ground(a, b, h, mu=0.6, live=(1.0, 0.0, 0.0), live_m=(0.0, 0.0, 0.0), weight=1.0, name="box"):
    """A block a x b x h (x, y, z) on the ground, its base on 4 corner points; dead load
    (0, 0, -weight), live load ``live`` (times weight) at the centroid."""
    corners = np.array([[-a / 2, -b / 2, 0], [a / 2, -b / 2, 0], [a / 2, b / 2, 0], [-a / 2, b / 2, 0]], float)
    normal = np.tile([0.0, 0.0, 1.0], (4, 1))   # from the ground (a) to the block (b)
    t1, t2 = tangent_frame(normal)
    return Structure3D(
        name=name, blocks=["B"], centroid=[[0, 0, h / 2]], dead=[[0, 0, -weight]],
        live=[np.asarray(live, float) * weight], live_m=[live_m], supports=["ground"], interfaces=["base"],
        iface_a=["ground"], iface_b=["B"], iface_polygon=[corners], point_interface=[0, 0, 0, 0],
        point=corners, normal=normal, tangent1=t1, tangent2=t2, mu=np.full(4, mu),
        polyhedra={"B": box_vertices((-a / 2, -b / 2, 0), (a / 2, b / 2, h))}).validate()


def transformed(s: Structure3D, R=np.eye(3), length=1.0, force=1.0, block_order=None, point_order=None,
                shift=(0.0, 0.0, 0.0)):
    """The same structure moved by the orthogonal map R (a rotation or a mirror; loads and
    gravity with it) and a shift, in other units (lengths times ``length``, forces times
    ``force``), with its blocks and contact points renumbered."""
    R = np.asarray(R, float)
    det = np.linalg.det(R)
    shift = np.asarray(shift, float)
    P = lambda x: (np.asarray(x) @ R.T) * length + shift  # noqa: E731
    V = lambda v: np.asarray(v) @ R.T  # noqa: E731
    nb, npt = s.n_blocks, s.n_points
    bo = np.arange(nb) if block_order is None else np.asarray(block_order)
    po = np.arange(npt) if point_order is None else np.asarray(point_order)
    normal = V(s.normal)[po]
    t1 = V(s.tangent1)[po]
    t2 = np.cross(normal, t1)  # right-handed again after a mirror
    return Structure3D(
        name=s.name, blocks=[s.blocks[j] for j in bo], centroid=P(s.centroid)[bo], dead=V(s.dead)[bo] * force,
        live=V(s.live)[bo] * force, supports=s.supports, interfaces=s.interfaces, iface_a=s.iface_a,
        iface_b=s.iface_b, iface_polygon=[P(p) for p in s.iface_polygon], point_interface=s.point_interface[po],
        point=P(s.point)[po], normal=normal, tangent1=t1, tangent2=t2, mu=s.mu[po],
        dead_m=det * V(s.dead_m)[bo] * force * length, live_m=det * V(s.live_m)[bo] * force * length,
        polyhedra={k: (P(v), f) for k, (v, f) in s.polyhedra.items()}).validate()


def stack_of_boxes(n, a, b, h, mu=0.6, live=(1.0, 0.0, 0.0)):
    """n equal blocks a x b x h stacked on the ground (interfaces on 4 corner points each);
    the whole stack turns about a base edge at alpha = a / (n h |cos|) or b / (n h |sin|)."""
    corners = np.array([[-a / 2, -b / 2], [a / 2, -b / 2], [a / 2, b / 2], [-a / 2, b / 2]], float)
    pts, faces, ia, ib = [], [], [], []
    for k in range(n):
        pts.append(np.column_stack([corners, np.full(4, k * h)]))
        ia.append("ground" if k == 0 else f"B{k}")
        ib.append(f"B{k + 1}")
    point = np.vstack(pts)
    normal = np.tile([0.0, 0.0, 1.0], (4 * n, 1))
    t1, t2 = tangent_frame(normal)
    blocks = [f"B{k + 1}" for k in range(n)]
    return Structure3D(
        name=f"stack{n}", blocks=blocks, centroid=[[0, 0, (k + 0.5) * h] for k in range(n)],
        dead=[[0, 0, -1.0]] * n, live=[list(live)] * n, supports=["ground"],
        interfaces=[f"j{k}" for k in range(n)], iface_a=ia, iface_b=ib, iface_polygon=pts,
        point_interface=np.repeat(np.arange(n), 4), point=point, normal=normal, tangent1=t1, tangent2=t2,
        mu=np.full(4 * n, mu),
        polyhedra={f"B{k + 1}": box_vertices((-a / 2, -b / 2, k * h), (a / 2, b / 2, (k + 1) * h))
                   for k in range(n)}).validate()
