#!/usr/bin/python3
"""A tracker that breaks hcpf's external-tracker protocol on purpose (tests).

    bad_tracker.py MODE [PIDFILE]

exit: writes a line to stderr and exits 3 before reading anything.
garbage: answers the hello, then answers frame 0 with a line that is not JSON.
wrong_frame: answers frame k with the tracks of frame k + 5.
bad_box: answers frame 0 with a track of width 0.
hang: answers the hello, then never answers a frame (sleeps in a child
  process too, so only a kill of the whole process group ends both).
chatty: writes 1 MiB to stderr per frame, and answers every frame correctly
  with no tracks (a child that would block on a full stderr pipe).
images: answers every frame with no tracks after checking that the frame's
  image is a PNG file that exists (exits 4 when it is not, 5 when the hello
  promised images and a frame has none).
leaves_child: answers every frame with no tracks; at the end message starts
  a child that holds its stdout for 100 s, then exits 0.
leaves_detached_child: the same, the child in a session of its own (outside
  the process group, so hcpf cannot end it) for 3 s.
PIDFILE: where to write this process's id (its process group's id).
"""
import json
import os
import subprocess
import sys
import time

mode = sys.argv[1]
if len(sys.argv) > 2:
    with open(sys.argv[2], "w") as f:
        f.write(str(os.getpid()))
if mode == "exit":
    print("bad_tracker: giving up at once", file=sys.stderr)
    sys.exit(3)
if mode == "ansi":
    print("\033[2Jbad_tracker:\a escape\rOVERWRITE", file=sys.stderr)
    sys.exit(3)


def send(obj):
    sys.stdout.write(json.dumps(obj) + "\n")
    sys.stdout.flush()


images = False
for line in sys.stdin:
    message = json.loads(line)
    if message["type"] == "hello":
        images = message["images"]
        print("bad_tracker: hello received", file=sys.stderr, flush=True)
        if mode == "control_name":
            send({"type": "ready", "protocol": 1, "name": "evil\u001b[31m\r\nINJECTED"})
        else:
            send({"type": "ready", "protocol": 1})
        continue
    if message["type"] == "end":
        if mode == "leaves_child":
            subprocess.Popen(["sleep", "100"])
        elif mode == "leaves_detached_child":
            subprocess.Popen(["sleep", "3"], start_new_session=True)
        sys.exit(0)
    frame = message["frame"]
    if mode == "garbage":
        print("bad_tracker: about to write garbage", file=sys.stderr, flush=True)
        sys.stdout.write("this is not json\n")
        sys.stdout.flush()
    elif mode == "wrong_frame":
        send({"type": "tracks", "frame": frame + 5, "tracks": []})
    elif mode == "bad_box":
        send({"type": "tracks", "frame": frame, "tracks": [{"id": 1, "box": [1, 2, 0, 4]}]})
    elif mode == "hang":
        subprocess.Popen(["sleep", "100"])
        time.sleep(100)
    elif mode == "images":
        path = message["image"]
        if images and path is None:
            sys.exit(5)
        if path is not None:
            with open(path, "rb") as f:
                if f.read(8) != b"\x89PNG\r\n\x1a\n":
                    sys.exit(4)
            print(f"bad_tracker: frame {frame} image {path}", file=sys.stderr, flush=True)
        send({"type": "tracks", "frame": frame, "tracks": []})
    elif mode in ("leaves_child", "leaves_detached_child"):
        send({"type": "tracks", "frame": frame, "tracks": []})
    elif mode == "chatty":
        sys.stderr.write(("x" * 1023 + "\n") * 1024)
        sys.stderr.flush()
        send({"type": "tracks", "frame": frame, "tracks": []})
