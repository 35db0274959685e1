#!/usr/bin/python3
"""A SORT-style multi-object tracker speaking hcpf's external-tracker protocol.

SORT (Bewley et al., "Simple Online and Realtime Tracking", ICIP 2016): one
constant-velocity Kalman filter per track on the box centre (u, v), area s and
aspect ratio r; detections matched to the tracks' predicted boxes by the
Hungarian algorithm on 1 - IoU, matches below an IoU threshold rejected; a
track is reported once it has `min_hits` consecutive matches (or in the first
`min_hits` frames) and deleted after `max_age` frames without one.

Protocol (docs/external-trackers.md, version 1): one JSON object per line on
stdin (hello, frame..., end); one per line on stdout (ready, tracks...).
Anything else goes to stderr. Needs numpy only (Debian's python3-numpy).

    sort_tracker.py [--max-age N] [--min-hits N] [--iou-threshold X]
"""

import argparse
import json
import sys

import numpy as np

PROTOCOL = 1


def hungarian(cost):
    """Minimum-cost assignment of a rectangular cost matrix.

    Returns (rows, cols) index arrays of the assigned pairs, min(n, m) of
    them. The O(n^2 m) shortest-augmenting-path form of the Hungarian method
    with row/column potentials (Kuhn-Munkres; the e-maxx formulation), rows
    <= columns (the matrix is transposed otherwise).
    """
    cost = np.asarray(cost, dtype=float)
    if cost.size == 0:
        return np.zeros(0, dtype=int), np.zeros(0, dtype=int)
    transposed = cost.shape[0] > cost.shape[1]
    if transposed:
        cost = cost.T
    n, m = cost.shape
    inf = np.inf
    u = np.zeros(n + 1)
    v = np.zeros(m + 1)
    p = np.zeros(m + 1, dtype=int)  # p[j]: row (1-based) assigned to column j; 0 = none
    way = np.zeros(m + 1, dtype=int)
    for i in range(1, n + 1):
        p[0] = i
        j0 = 0
        minv = np.full(m + 1, inf)
        used = np.zeros(m + 1, dtype=bool)
        while True:
            used[j0] = True
            i0 = p[j0]
            # Reduced costs of row i0 against every unused column.
            cur = cost[i0 - 1, :] - u[i0] - v[1:]
            free = ~used[1:]
            better = free & (cur < minv[1:])
            minv[1:][better] = cur[better]
            way[1:][better] = j0
            candidates = np.where(free, minv[1:], inf)
            j1 = int(np.argmin(candidates)) + 1
            delta = candidates[j1 - 1]
            # Potentials: used columns (and their rows) by +delta / -delta.
            used_cols = np.nonzero(used)[0]
            u[p[used_cols]] += delta
            v[used_cols] -= delta
            minv[1:][free] -= delta
            j0 = j1
            if p[j0] == 0:
                break
        while True:  # augment along the path
            j1 = way[j0]
            p[j0] = p[j1]
            j0 = j1
            if j0 == 0:
                break
    cols = np.nonzero(p[1:])[0]
    rows = p[1:][cols] - 1
    order = np.argsort(rows)
    rows, cols = rows[order], cols[order]
    if transposed:
        rows, cols = cols, rows
        order = np.argsort(rows)
        rows, cols = rows[order], cols[order]
    return rows.astype(int), cols.astype(int)


def iou_matrix(a, b):
    """IoU of every box of a (n x 4, left/top/w/h) with every box of b."""
    if len(a) == 0 or len(b) == 0:
        return np.zeros((len(a), len(b)))
    a = np.asarray(a)[:, None, :]
    b = np.asarray(b)[None, :, :]
    left = np.maximum(a[..., 0], b[..., 0])
    top = np.maximum(a[..., 1], b[..., 1])
    right = np.minimum(a[..., 0] + a[..., 2], b[..., 0] + b[..., 2])
    bottom = np.minimum(a[..., 1] + a[..., 3], b[..., 1] + b[..., 3])
    inter = np.clip(right - left, 0, None) * np.clip(bottom - top, 0, None)
    union = a[..., 2] * a[..., 3] + b[..., 2] * b[..., 3] - inter
    return np.where(union > 0, inter / np.maximum(union, 1e-12), 0.0)


def box_to_z(box):
    left, top, w, h = box
    return np.array([left + w / 2.0, top + h / 2.0, w * h, w / h])


def x_to_box(x):
    s = max(float(x[2]), 1e-6)
    r = max(float(x[3]), 1e-6)
    w = np.sqrt(s * r)
    h = s / w
    return [float(x[0]) - w / 2.0, float(x[1]) - h / 2.0, float(w), float(h)]


class KalmanBoxTrack:
    """Constant-velocity Kalman filter on (u, v, s, r, u', v', s'), SORT's values."""

    F = np.eye(7)
    F[0, 4] = F[1, 5] = F[2, 6] = 1.0
    H = np.eye(4, 7)
    R = np.diag([1.0, 1.0, 10.0, 10.0])
    Q = np.diag([1.0, 1.0, 1.0, 1.0, 0.01, 0.01, 1e-4])

    def __init__(self, box, score, track_id):
        self.x = np.zeros(7)
        self.x[:4] = box_to_z(box)
        self.P = np.diag([10.0, 10.0, 10.0, 10.0, 1e4, 1e4, 1e4])
        self.id = track_id
        self.score = score
        self.hits = 1
        self.hit_streak = 1
        self.time_since_update = 0

    def predict(self):
        if self.x[2] + self.x[6] <= 0:  # the area must stay positive
            self.x[6] = 0.0
        self.x = self.F @ self.x
        self.P = self.F @ self.P @ self.F.T + self.Q
        if self.time_since_update > 0:
            self.hit_streak = 0
        self.time_since_update += 1
        return x_to_box(self.x)

    def update(self, box, score):
        z = box_to_z(box)
        y = z - self.H @ self.x
        S = self.H @ self.P @ self.H.T + self.R
        K = self.P @ self.H.T @ np.linalg.inv(S)
        self.x = self.x + K @ y
        self.P = (np.eye(7) - K @ self.H) @ self.P
        self.score = score
        self.hits += 1
        self.hit_streak += 1
        self.time_since_update = 0


class Sort:
    def __init__(self, max_age, min_hits, iou_threshold):
        self.max_age = max_age
        self.min_hits = min_hits
        self.iou_threshold = iou_threshold
        self.tracks = []
        self.next_id = 1
        self.frames_seen = 0

    def step(self, boxes, scores):
        self.frames_seen += 1
        predicted = [t.predict() for t in self.tracks]
        iou = iou_matrix(boxes, predicted)
        matched_dets = set()
        matched_tracks = set()
        if iou.size:
            rows, cols = hungarian(1.0 - iou)
            for d, t in zip(rows, cols):
                if iou[d, t] >= self.iou_threshold:
                    self.tracks[t].update(boxes[d], scores[d])
                    matched_dets.add(int(d))
                    matched_tracks.add(int(t))
        for d in range(len(boxes)):
            if d not in matched_dets:
                self.tracks.append(KalmanBoxTrack(boxes[d], scores[d], self.next_id))
                self.next_id += 1
        out = []
        for t in self.tracks:
            if t.time_since_update == 0 and (
                t.hit_streak >= self.min_hits or self.frames_seen <= self.min_hits
            ):
                out.append({"id": t.id, "box": x_to_box(t.x), "score": float(t.score)})
        self.tracks = [t for t in self.tracks if t.time_since_update <= self.max_age]
        out.sort(key=lambda t: t["id"])
        return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-age", type=int, default=3, help="frames a track survives unmatched")
    parser.add_argument("--min-hits", type=int, default=3, help="matches before a track is reported")
    parser.add_argument("--iou-threshold", type=float, default=0.3, help="least IoU of a match")
    args = parser.parse_args()
    tracker = Sort(args.max_age, args.min_hits, args.iou_threshold)

    def send(obj):
        sys.stdout.write(json.dumps(obj, separators=(",", ":")) + "\n")
        sys.stdout.flush()

    for line in sys.stdin:
        message = json.loads(line)
        kind = message.get("type")
        if kind == "hello":
            if message.get("protocol") != PROTOCOL:
                print(f"sort_tracker: protocol {message.get('protocol')} unknown", file=sys.stderr)
                return 1
            send({"type": "ready", "protocol": PROTOCOL, "name": "sort"})
        elif kind == "frame":
            detections = message["detections"]
            boxes = [d["box"] for d in detections]
            scores = [d.get("score", 1.0) for d in detections]
            tracks = tracker.step(boxes, scores)
            send({"type": "tracks", "frame": message["frame"], "tracks": tracks})
        elif kind == "end":
            return 0
        else:
            print(f"sort_tracker: unknown message type {kind!r}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
