#!/usr/bin/python3
"""Unit tests of sort_tracker.py (ctest: SortTracker.*; run by hand with /usr/bin/python3).

The Hungarian solver is checked against brute force over every assignment of
random matrices (expected values computed by enumeration, not by the solver);
the Kalman track against a target moving at constant velocity.
"""
import itertools
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sort_tracker  # noqa: E402


def brute_force(cost):
    n, m = cost.shape
    if n <= m:
        return min(sum(cost[i, p[i]] for i in range(n)) for p in itertools.permutations(range(m), n))
    return min(sum(cost[p[j], j] for j in range(m)) for p in itertools.permutations(range(n), m))


class Hungarian(unittest.TestCase):
    def test_matches_brute_force_on_random_matrices(self):
        rng = np.random.default_rng(7)
        for n, m in [(1, 1), (2, 3), (3, 2), (4, 4), (5, 3), (3, 6), (6, 6)]:
            for _ in range(30):
                cost = rng.random((n, m))
                rows, cols = sort_tracker.hungarian(cost)
                self.assertEqual(len(rows), min(n, m))
                self.assertEqual(len(set(rows)), len(rows))
                self.assertEqual(len(set(cols)), len(cols))
                self.assertAlmostEqual(cost[rows, cols].sum(), brute_force(cost), places=9)

    def test_empty(self):
        rows, cols = sort_tracker.hungarian(np.zeros((0, 3)))
        self.assertEqual(len(rows), 0)


class Tracking(unittest.TestCase):
    def test_constant_velocity_target_keeps_one_id_and_is_followed(self):
        sort = sort_tracker.Sort(max_age=3, min_hits=3, iou_threshold=0.3)
        ids = set()
        for k in range(30):
            box = [10.0 + 2.0 * k, 20.0 + 1.0 * k, 20.0, 10.0]
            out = sort.step([box], [1.0])
            self.assertEqual(len(out), 1)  # reported from the first frame (frames <= min_hits)
            ids.add(out[0]["id"])
            # The Kalman estimate lies within 1 px of the measured box (its
            # measurement noise is 1 px^2 on the centre).
            self.assertTrue(np.allclose(out[0]["box"][:2], box[:2], atol=1.0), (k, out, box))
        self.assertEqual(ids, {1})

    def test_a_missed_frame_within_max_age_keeps_the_id(self):
        sort = sort_tracker.Sort(max_age=3, min_hits=1, iou_threshold=0.3)
        for k in range(10):
            sort.step([[10.0 + k, 20.0, 20.0, 10.0]], [1.0])
        self.assertEqual(sort.step([], []), [])
        out = sort.step([[22.0, 20.0, 20.0, 10.0]], [1.0])
        self.assertEqual([t["id"] for t in out], [1])


if __name__ == "__main__":
    unittest.main()
