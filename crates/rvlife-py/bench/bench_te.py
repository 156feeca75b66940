"""Overhead of the Python call over the Rust call for `te` (10 um uniform wear, loaded TE at
412 N m, the built-in example): times `rvlife.te` here and compares its median with the
criterion median of the same library call (`cargo bench -p rvlife --bench study --
api_te_10um_412nm`, read from target/criterion).

    python crates/rvlife-py/bench/bench_te.py [repeats]
"""

import json
import statistics
import sys
import time
from pathlib import Path

import rvlife

ROOT = Path(__file__).resolve().parents[3]


def main() -> None:
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 30
    cfg = rvlife.example()
    rvlife.te(cfg, wear_um=10.0, torque_nm=412.0)  # warm-up
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        rvlife.te(cfg, wear_um=10.0, torque_nm=412.0)
        times.append(time.perf_counter() - t0)
    py = statistics.median(times)
    print(f"python rvlife.te: median {py * 1e3:.2f} ms over {repeats} calls "
          f"(min {min(times) * 1e3:.2f}, max {max(times) * 1e3:.2f})")
    est = ROOT / "target" / "criterion" / "api_te_10um_412nm" / "new" / "estimates.json"
    if est.is_file():
        rust = json.loads(est.read_text())["median"]["point_estimate"] * 1e-9
        print(f"rust api::te (criterion median): {rust * 1e3:.2f} ms")
        print(f"overhead of the Python call: {100 * (py - rust) / rust:+.2f} %")
    else:
        print(f"no criterion result at {est}: run cargo bench -p rvlife --bench study -- api_te_10um_412nm")


if __name__ == "__main__":
    main()
