"""Shared by the tests of scripts/plot_*.py: import a script as a module (to inspect the figures it builds), run it
as a program (to check exit codes, messages and files), and check where legends sit."""

import contextlib
import importlib.util
import io
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.normpath(os.path.join(HERE, "..", ".."))
SCRIPTS = os.path.join(SOURCE_DIR, "scripts")

HAVE_MATPLOTLIB = importlib.util.find_spec("matplotlib") is not None
NO_MATPLOTLIB = "this python3 has no matplotlib: run with /usr/bin/python3 (Debian's python3-matplotlib)"


def load_script(name):
    """scripts/NAME.py as a module (its main() does not run)."""
    spec = importlib.util.spec_from_file_location(name, os.path.join(SCRIPTS, name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_script(name, *arguments, cwd=None):
    """Runs scripts/NAME.py with this interpreter; returns the CompletedProcess (text stdout and stderr)."""
    return subprocess.run([sys.executable, os.path.join(SCRIPTS, name + ".py"), *arguments], capture_output=True,
                          text=True, timeout=60, cwd=cwd, env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1"))


def call_main(module, *arguments):
    """Runs module.main(arguments) in this process (quicker than a program for the many bad-input cases); returns
    (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    code = 0
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            module.main(list(arguments))
        except SystemExit as exit:
            code = exit.code if isinstance(exit.code, int) else 1
    return code, out.getvalue(), err.getvalue()


def legends_of(figure):
    return list(figure.legends) + [axis.get_legend() for axis in figure.axes if axis.get_legend() is not None]


def legend_texts(figure):
    return [text.get_text() for legend in legends_of(figure) for text in legend.get_texts()]


def legends_covering_axes(figure):
    """(legend texts, axis title) pairs where a legend's box overlaps the data area of a visible axis."""
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    overlaps = []
    for legend in legends_of(figure):
        box = legend.get_window_extent(renderer)
        for axis in figure.axes:
            if axis.get_visible() and box.overlaps(axis.get_window_extent(renderer)):
                overlaps.append(([t.get_text() for t in legend.get_texts()], axis.get_title()))
    return overlaps


def is_png(path):
    with open(path, "rb") as handle:
        return handle.read(8) == b"\x89PNG\r\n\x1a\n"


class TempDirTest(unittest.TestCase):
    """A test with its own scratch folder (self.dir), removed afterwards with every figure closed."""


    def setUp(self):
        self.temp = tempfile.TemporaryDirectory()
        self.dir = self.temp.name

    def tearDown(self):
        import matplotlib.pyplot as plt

        plt.close("all")
        self.temp.cleanup()

    def write(self, relative, text):
        path = os.path.join(self.dir, relative)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as handle:
            handle.write(text)
        return path
