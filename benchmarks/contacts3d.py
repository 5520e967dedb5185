"""Contact search in 3D: box buildings of growing size (blocks, interfaces, seconds).

    PYTHONPATH=. python benchmarks/contacts3d.py [max_blocks]
"""
import argparse
import time

from lamodel.geometry.generators3d import box_building
from lamodel.io.json3d import structure3d_from_spec


def main(limit=10_000):
    print(f"{'courses':>7} {'plan':>9} {'blocks':>7} {'interfaces':>10} {'points':>8} {'seconds':>8}")
    for courses, length, width in ((12, 4.0, 3.0), (30, 8.0, 6.0), (50, 12.0, 10.0), (60, 18.0, 15.0)):
        spec = box_building(length, width, courses, door=(1.6, 2.4, 9), windows=())
        n = sum(1 for b in spec["blocks"] if not b.get("support"))
        if n > limit:
            break
        t = time.perf_counter()
        s = structure3d_from_spec(spec)
        dt = time.perf_counter() - t
        print(f"{courses:>7} {f'{length:g}x{width:g}':>9} {s.n_blocks:>7} {s.n_interfaces:>10} {s.n_points:>8} {dt:>8.2f}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("max_blocks", type=int, nargs="?", default=10_000, help="the largest building (default 10,000)")
    main(ap.parse_args().max_blocks)
