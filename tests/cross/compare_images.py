#!/usr/bin/env python3
"""A render of the target build against the host build's: the same pixels.

    compare_images.py HOST.png TARGET.png [--max-level N]

Equal files pass at once. Otherwise both are decoded and compared channel by channel: the largest
difference (in 8-bit levels), how many pixels differ and where the first is are printed, and the
check passes only when no channel differs by more than --max-level (default 0: byte for byte).
"""
import argparse
import sys

from PIL import Image, ImageChops


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("host")
    ap.add_argument("target")
    ap.add_argument("--max-level", type=int, default=0)
    a = ap.parse_args()
    with open(a.host, "rb") as f:
        host_bytes = f.read()
    try:
        with open(a.target, "rb") as f:
            target_bytes = f.read()
    except OSError as e:
        sys.exit(f"compare_images: {a.target}: {e.strerror}")
    if host_bytes == target_bytes:
        print(f"compare_images: {a.target}: equal to the host's, byte for byte")
        return
    host, target = Image.open(a.host).convert("RGBA"), Image.open(a.target).convert("RGBA")
    if host.size != target.size:
        sys.exit(f"compare_images: {a.target}: {target.size[0]}x{target.size[1]}, the host's is {host.size[0]}x{host.size[1]}")
    diff = ImageChops.difference(host, target)
    worst = max(high for _, high in diff.getextrema())
    data = diff.getdata()
    differing = sum(1 for p in data if any(p))
    first = next(i for i, p in enumerate(data) if any(p)) if differing else 0
    w = host.size[0]
    verdict = "within" if worst <= a.max_level else "over"
    print(f"compare_images: {a.target}: {differing} of {w * host.size[1]} pixels differ, at most {worst} levels "
          f"(first at x {first % w}, y {first // w}; {verdict} the bound of {a.max_level})")
    if worst > a.max_level:
        sys.exit(1)


if __name__ == "__main__":
    main()
