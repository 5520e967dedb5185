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
