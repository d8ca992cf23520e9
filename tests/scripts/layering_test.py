"""cmake/orcs_layering.cmake, the dependency rule of docs/architecture.md, on a small project of its own: the real
module over a tree with the project's top folders and the sub-folders the rule holds apart (clients/runtime,
clients/gap, clients/batch). A clean tree configures; a runtime file including a client's header, a runtime target
linking a client's library, a gap file including orcs-batch's, a broker file including the model each fail the
configuration with one line naming the culprit. Configures only; builds nothing."""

import os
import subprocess
import tempfile
import textwrap
import unittest

from script_helpers import SOURCE_DIR

FOLDERS = ["base", "proto", "model", "net", "broker", "worker", "viewer", "clients", "hardware"]


class LayeringTest(unittest.TestCase):
    def make_tree(self, root, runtime_links="orcs_broker", runtime_include="broker/broker.h",
                  gap_include="clients/runtime/job_runner.h", broker_include="net/dealer.h"):
        files = {
            "CMakeLists.txt": f"""
                cmake_minimum_required(VERSION 3.22)
                project(layering LANGUAGES CXX)
                include({SOURCE_DIR}/cmake/orcs_link_check.cmake)
                include({SOURCE_DIR}/cmake/orcs_layering.cmake)
                foreach(folder {" ".join(FOLDERS)})
                  add_subdirectory(${{folder}})
                endforeach()
                orcs_check_layering()
                """,
            "broker/CMakeLists.txt": "add_library(orcs_broker STATIC broker.cc)",
            "broker/broker.cc": f'#include "{broker_include}"\n',
            "clients/CMakeLists.txt": """
                add_subdirectory(runtime)
                add_library(orcs_batch STATIC batch/sweep.cc)
                target_link_libraries(orcs_batch PUBLIC orcs_client_runtime)
                add_library(orcs_gap STATIC gap/gap.cc)
                target_link_libraries(orcs_gap PUBLIC orcs_client_runtime)
                """,
            "clients/runtime/CMakeLists.txt": f"""
                add_library(orcs_client_runtime STATIC job_runner.cc)
                target_link_libraries(orcs_client_runtime PUBLIC {runtime_links})
                """,
            "clients/runtime/job_runner.cc": f'#include "{runtime_include}"\n',
            "clients/batch/sweep.cc": '#include "clients/runtime/job_runner.h"\n',
            "clients/gap/gap.cc": f'#include "{gap_include}"\n',
        }
        for folder in FOLDERS:
            files.setdefault(f"{folder}/CMakeLists.txt", "")
        for path, text in files.items():
            full = os.path.join(root, path)
            os.makedirs(os.path.dirname(full), exist_ok=True)
            with open(full, "w") as out:
                out.write(textwrap.dedent(text))

    def configure(self, **tree):
        with tempfile.TemporaryDirectory() as tmp:
            source = os.path.join(tmp, "src")
            self.make_tree(source, **tree)
            done = subprocess.run(["cmake", "-S", source, "-B", os.path.join(tmp, "build")],
                                  capture_output=True, text=True, timeout=120)
            return done.returncode, " ".join(done.stderr.split())  # CMake wraps its messages

    def test_a_tree_that_keeps_the_rule_configures(self):
        code, errors = self.configure()
        self.assertEqual(code, 0, errors)

    def test_the_runtime_including_a_clients_header_fails_naming_the_file(self):
        code, errors = self.configure(runtime_include="clients/batch/sweep_grid.h")
        self.assertNotEqual(code, 0)
        self.assertIn('orcs layering: clients/runtime/job_runner.cc includes "clients/batch/sweep_grid.h"', errors)

    def test_the_runtime_linking_a_clients_library_fails_naming_the_target(self):
        code, errors = self.configure(runtime_links="orcs_broker orcs_batch")
        self.assertNotEqual(code, 0)
        self.assertIn("orcs layering: orcs_client_runtime (clients/runtime/) links orcs_batch from clients/batch/",
                      errors)

    def test_orcs_gap_including_orcs_batchs_code_fails(self):
        code, errors = self.configure(gap_include="clients/batch/sweep_grid.h")
        self.assertNotEqual(code, 0)
        self.assertIn('orcs layering: clients/gap/gap.cc includes "clients/batch/sweep_grid.h"', errors)

    def test_the_broker_including_the_model_fails(self):
        code, errors = self.configure(broker_include="model/scene/simulation.h")
        self.assertNotEqual(code, 0)
        self.assertIn('orcs layering: broker/broker.cc includes "model/scene/simulation.h" from model/', errors)


if __name__ == "__main__":
    unittest.main()
