"""scripts/build.sh on a build folder a newcomer configured by hand with a plain `cmake -B build` (issue 52's paper
cut): it used to stop on CMake's "generator: Ninja does not match the generator used previously: Unix Makefiles";
now it builds with the folder's own generator and says how to get Ninja. Configures a folder of its own (tests off,
so quick) and builds one small target in it."""

import os
import shutil
import subprocess
import tempfile
import unittest

from script_helpers import SOURCE_DIR


class BuildScriptTest(unittest.TestCase):
    def test_a_folder_configured_by_plain_cmake_is_built_with_its_own_generator(self):
        with tempfile.TemporaryDirectory() as tmp:
            folder = os.path.join(tmp, "build")
            plain = subprocess.run(["cmake", "-S", SOURCE_DIR, "-B", folder, "-G", "Unix Makefiles",
                                    "-DORCS_BUILD_TESTS=OFF"], capture_output=True, text=True, timeout=300)
            self.assertEqual(plain.returncode, 0, plain.stderr)
            built = subprocess.run([os.path.join(SOURCE_DIR, "scripts", "build.sh"), "-DORCS_BUILD_TESTS=OFF"],
                                   capture_output=True, text=True, timeout=300,
                                   env=dict(os.environ, BUILD_DIR=folder, TARGET="orcs_base"))
            self.assertEqual(built.returncode, 0, built.stderr)
            self.assertNotIn("does not match", built.stderr)
            self.assertIn('configured with "Unix Makefiles"', built.stderr)
            self.assertIn("remove", built.stderr, "says how to get Ninja instead")
            self.assertTrue(os.path.isfile(os.path.join(folder, "base", "liborcs_base.a")))


if __name__ == "__main__":
    unittest.main()
