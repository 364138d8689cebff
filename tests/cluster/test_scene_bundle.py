"""The Ray driver's scene reading without Ray: hostile JSON is refused with one UsageError line (ctest -L unit)."""
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "engine", "cluster"))

from fredholm_ray import scene_bundle  # noqa: E402  (needs no Ray)
from fredholm_ray.plan import UsageError  # noqa: E402

BAD = os.path.join(ROOT, "tests", "robustness", "bad")


class SceneBundleTest(unittest.TestCase):
    def test_deep_nesting_is_refused_before_parsing(self):
        # 30,000 nested arrays: Python's json module would stop with a RecursionError (a traceback, not a line).
        for name in ("deep_nesting.gltf", "deep_nesting.glb"):
            with self.assertRaises(UsageError) as caught:
                scene_bundle.read_gltf_json(os.path.join(BAD, name))
            self.assertIn("nests arrays and objects 30001 levels deep, more than the limit of 1000", str(caught.exception))

    def test_brackets_in_strings_do_not_count(self):
        self.assertEqual(scene_bundle.json_nesting_depth(b'{"a": "[[[[\\"[[", "b": [[1]]}'), 3)

    def test_scenes_we_ship_are_read(self):
        document = scene_bundle.read_gltf_json(os.path.join(ROOT, "scenes", "cornell.gltf"))
        self.assertEqual(document["asset"]["version"], "2.0")


if __name__ == "__main__":
    unittest.main()
