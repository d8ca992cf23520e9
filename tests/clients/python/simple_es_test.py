"""clients/python/examples/simple_es.py with a small budget (3 generations × 8 genomes) against a real orcs-broker
and two real orcs-worker processes on 127.0.0.1: it exits 0, prints one line per generation, every generation's
best fitness is finite, and the best so far never decreases (the strategy is elitist and every genome meets the
same parameter sets). A second run with the same seeds prints the same first generation: the run is reproducible.

Run by CTest (tests/clients/python/CMakeLists.txt) with ORCS_BIN and ORCS_PYTHON_PATH set.
"""

import math
import os
import re
import subprocess
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, HERE)

from local_cluster import LocalCluster  # noqa: E402

EXAMPLE = os.path.join(SOURCE_DIR, "clients", "python", "examples", "simple_es.py")
LINE = re.compile(r"generation (\d+): best (\S+) mean (\S+) best-so-far (\S+) \((\d+)/(\d+) ok, .*\)")


class SimpleEsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.cluster = LocalCluster(workers=2, heartbeat=0.2)

    @classmethod
    def tearDownClass(cls):
        cls.cluster.close()

    def run_example(self, generations):
        return subprocess.run([sys.executable, EXAMPLE, "--broker", self.cluster.clients, "--heartbeat", "0.2",
                               "--generations", str(generations), "--population", "8", "--parents", "2", "--seed",
                               "7", "--timeout", "120"], capture_output=True, text=True, timeout=400)

    def test_three_generations_improve_or_hold_the_best_fitness(self):
        run = self.run_example(3)
        self.assertEqual(run.returncode, 0, run.stderr + run.stdout)
        lines = [LINE.fullmatch(line) for line in run.stdout.splitlines() if line.startswith("generation")]
        self.assertEqual(len(lines), 3, run.stdout)
        self.assertTrue(all(lines), run.stdout)
        self.assertEqual([int(line.group(1)) for line in lines], [0, 1, 2])
        best = [float(line.group(2)) for line in lines]
        so_far = [float(line.group(4)) for line in lines]
        self.assertTrue(all(math.isfinite(value) for value in best + so_far), run.stdout)
        self.assertEqual(so_far, sorted(so_far), "elitist: the best so far never decreases")
        self.assertEqual(so_far[-1], max(best), "the best so far is the best of every generation")
        self.assertEqual([line.group(5, 6) for line in lines], [("8", "8")] * 3)
        self.assertRegex(run.stdout, r"best fitness \S+ with genome \[[^]]+\]")

        # The same seeds, the same run: the first generation again has the same fitness values, to the digit.
        again = self.run_example(1)
        self.assertEqual(again.returncode, 0, again.stderr)
        self.assertEqual([m.group(2, 3, 4) for m in map(LINE.fullmatch, again.stdout.splitlines()) if m],
                         [lines[0].group(2, 3, 4)])

    def test_no_broker_is_exit_code_two_with_one_line(self):
        run = subprocess.run([sys.executable, EXAMPLE, "--broker", "tcp://127.0.0.1:1", "--generations", "1"],
                             capture_output=True, text=True, timeout=60)
        self.assertEqual(run.returncode, 2, run.stdout)
        self.assertEqual(run.stderr.strip().count("\n"), 0, run.stderr)
        self.assertIn("no broker answering at tcp://127.0.0.1:1", run.stderr)


if __name__ == "__main__":
    unittest.main()
