#!/usr/bin/python3
"""The peer of orcs's broker dispatch benchmark: empty tasks through Dask distributed on loopback.

A LocalCluster on 127.0.0.1 with W worker processes (one thread each, as an orcs worker runs one job at a time)
and its scheduler; one client submits N no-op tasks at once (client.map) and gathers all N results, like
BM_BrokerDispatchEmptyJobs submits N empty jobs and takes every result. One warm-up batch first, then --repeat
timed batches; prints one line per batch and a final summary line:

    dask: tasks=10000 workers=2 median=1234.5 min=1200.0 max=1300.0 tasks/s

Run with Debian's python (/usr/bin/python3, package python3-distributed); scripts/bench_batch.sh does.
"""
import argparse
import statistics
import sys
import time


def noop(i):
    return i


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tasks", type=int, default=10000, help="tasks per batch (default 10000)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--repeat", type=int, default=5, help="timed batches (default 5)")
    args = parser.parse_args()
    if args.tasks < 1 or args.workers < 1 or args.repeat < 1:
        parser.error("--tasks, --workers and --repeat must be positive")

    try:
        import dask
        from dask.distributed import Client, LocalCluster
    except ImportError as error:
        sys.exit(f"bench_dask.py: {error}; install Debian's python3-distributed and run /usr/bin/python3")

    dask.config.set({"distributed.logging.distributed": "error"})
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, silence_logs=40) as cluster, Client(cluster) as client:
        client.wait_for_workers(args.workers, timeout=60)
        # Warm-up: the workers import the function and open their connections.
        warm = min(args.tasks, 1000)
        client.gather(client.map(noop, range(warm), key=[f"warm-{i}" for i in range(warm)]))
        rates = []
        for batch in range(args.repeat):
            keys = [f"b{batch}-{i}" for i in range(args.tasks)]  # unique keys: no result is reused from a batch before
            start = time.perf_counter()
            futures = client.map(noop, range(args.tasks), key=keys, pure=False)
            results = client.gather(futures)
            seconds = time.perf_counter() - start
            if len(results) != args.tasks or results[-1] != args.tasks - 1:
                sys.exit(f"bench_dask.py: batch {batch} returned {len(results)} results")
            del futures
            rates.append(args.tasks / seconds)
            print(f"dask: batch {batch}: {args.tasks} tasks in {seconds:.3f} s = {rates[-1]:.1f} tasks/s", flush=True)
        print(f"dask: tasks={args.tasks} workers={args.workers} median={statistics.median(rates):.1f} "
              f"min={min(rates):.1f} max={max(rates):.1f} tasks/s dask={dask.__version__}", flush=True)


if __name__ == "__main__":
    main()
