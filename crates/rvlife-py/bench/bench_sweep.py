"""The Monte Carlo sweep on a two-worker LocalCluster against the run in this process:
60 samples of the built-in example with its tolerances, two stages (0 and 7500 h) and no life
search beyond them (the README's figures).

    python crates/rvlife-py/bench/bench_sweep.py [samples] [repeats]

Prints the wall time of each run (median of ``repeats``) and the ratios; every run's records
are checked to be the same bytes.
"""

import statistics
import sys
import time

import rvlife


def timed(f, repeats):
    times, result = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), result


def main() -> None:
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 60
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    cfg = rvlife.example().replace({"wear.stage_hours": [0.0, 7500.0], "life.max_hours": 7500.0})
    from dask.distributed import Client, LocalCluster

    serial1, r1 = timed(lambda: rvlife.montecarlo(cfg, samples=samples, threads=1), repeats)
    print(f"serial, one core:                  {serial1:7.1f} s")
    serial2, r2 = timed(lambda: rvlife.montecarlo(cfg, samples=samples), repeats)
    print(f"in this process, both cores:       {serial2:7.1f} s")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with Client(cluster) as client:
            client.run(lambda: __import__("rvlife"))
            dask, r3 = timed(lambda: rvlife.sweep(rvlife.MonteCarlo(cfg, samples=samples), client), repeats)
    print(f"Dask, 2 workers x 1 thread:        {dask:7.1f} s")
    assert r1.samples.equals(r2.samples) and r2.samples.equals(r3.samples), "records differ"
    assert r1.stages.equals(r3.stages), "records differ"
    print(f"Dask against one core: {serial1 / dask:.2f} x; against both cores in this process: {serial2 / dask:.2f} x")


if __name__ == "__main__":
    main()
