#!/usr/bin/env python3
"""A (mu + lambda) evolution strategy in pure Python that evolves a scenario's genome through an orcs broker.

Each generation is one batch: lambda mutated genomes (the first generation: the scenario's genome and lambda - 1
mutants of it), evaluated by the broker's workers; the mu best of parents and offspring become the next parents.
Every genome is evaluated with the same job seed (--eval-seed), so it meets the same randomised parameter sets
and its fitness is a fixed number: the strategy is elitist and the best fitness never decreases. All randomness
comes from random.Random(--seed): the same options give the same run.

    build/bin/orcs-broker &                                                 # clients :5555, workers :5556
    build/bin/orcs-worker --connect tcp://127.0.0.1:5556 &                  # one or more
    /usr/bin/python3 clients/python/examples/simple_es.py --generations 10 --population 8

Prints one line per generation (best and mean fitness of the generation's batch, the best so far) and the best
genome at the end. Exit 0; 1 when a generation had no ok job; 2 on bad input or when no broker answers.
"""

import argparse
import math
import os
import random
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # clients/python

from orcs_client import BatchClient, OrcsClientError, Scenario  # noqa: E402

_SOURCE_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
DEFAULT_SCENARIO = os.path.normpath(os.path.join(_SOURCE_DIR, "scenarios", "examples", "swing_oscillator.json"))


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--broker", default="tcp://127.0.0.1:5555", help="the broker's client endpoint")
    parser.add_argument("--scenario", default=DEFAULT_SCENARIO, help="scenario file (default: swing_oscillator)")
    parser.add_argument("--generations", type=int, default=10, help="generations, one batch each (default 10)")
    parser.add_argument("--population", type=int, default=8, help="offspring per generation, lambda (default 8)")
    parser.add_argument("--parents", type=int, default=2, help="parents kept, mu (default 2)")
    parser.add_argument("--sigma", type=float, default=0.05,
                        help="mutation step as a fraction of each gene's initial size, at least 1 (default 0.05)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the strategy's random numbers (default 1)")
    parser.add_argument("--eval-seed", type=int, default=1, help="job seed every genome is evaluated with")
    parser.add_argument("--heartbeat", type=float, default=1.0, help="seconds; the broker's value (default 1)")
    parser.add_argument("--timeout", type=float, default=600.0,
                        help="seconds to wait for the next result before giving up (default 600)")
    parser.add_argument("--orcs-batch", default=None, help="the orcs-batch program (default: the build's)")
    options = parser.parse_args(argv)
    for name in ("generations", "population", "parents"):
        if getattr(options, name) < 1:
            parser.error("--%s must be at least 1" % name)
    if options.parents > options.population:
        parser.error("--parents must not exceed --population")
    if not (math.isfinite(options.sigma) and options.sigma > 0):
        parser.error("--sigma must be a positive number")
    return options


def mutate(genome, steps, rng):
    """A copy of `genome` with Gaussian noise of each gene's step added."""
    return [gene + rng.gauss(0.0, step) for gene, step in zip(genome, steps)]


def evaluate(client, scenario, genomes, eval_seed, timeout):
    """Fitness of each genome (-inf for a job that did not end ok) from one batch, and the batch's ok count."""
    batch = client.submit(scenario.job(genome, seed=eval_seed) for genome in genomes)
    fitness = []
    for result in batch.collect(timeout=timeout):
        if not result.ok:
            print("  %s: %s: %s" % (result.job_id, result.status, result.message), file=sys.stderr)
        fitness.append(result.fitness if result.ok else -math.inf)
    return fitness


def run(options):
    scenario = Scenario.load(options.scenario, orcs_batch=options.orcs_batch)
    start = scenario.genome
    if not isinstance(start, list) or not start:
        raise OrcsClientError("%s: needs a \"genome\" of numbers to start from" % options.scenario)
    steps = [options.sigma * max(1.0, abs(gene)) for gene in start]
    rng = random.Random(options.seed)
    parents = []  # (fitness, genome), best first
    with BatchClient(options.broker, heartbeat=options.heartbeat) as client:
        for generation in range(options.generations):
            if generation == 0:
                offspring = [list(start)] + [mutate(start, steps, rng) for _ in range(options.population - 1)]
            else:
                offspring = [mutate(rng.choice(parents)[1], steps, rng) for _ in range(options.population)]
            began = time.monotonic()
            fitness = evaluate(client, scenario, offspring, options.eval_seed, options.timeout)
            seconds = time.monotonic() - began
            ok = [value for value in fitness if math.isfinite(value)]
            if not ok:
                print("generation %d: no job ended ok" % generation)
                return 1
            # Stable sort on fitness alone: ties keep the older genome first, so a run is reproducible.
            parents = sorted(parents + list(zip(fitness, offspring)), key=lambda pair: -pair[0])[:options.parents]
            print("generation %d: best %.6f mean %.6f best-so-far %.6f (%d/%d ok, %.2f s, %.2f jobs/s)"
                  % (generation, max(ok), sum(ok) / len(ok), parents[0][0], len(ok), len(fitness), seconds,
                     len(fitness) / seconds), flush=True)
    best_fitness, best_genome = parents[0]
    print("best fitness %r with genome [%s]" % (best_fitness, ", ".join(repr(gene) for gene in best_genome)))
    return 0


def main(argv=None):
    options = parse_arguments(argv)
    try:
        return run(options)
    except (OrcsClientError, ValueError) as error:
        print("simple_es: %s" % error, file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
