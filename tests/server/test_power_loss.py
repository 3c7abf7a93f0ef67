"""A finished job's images survive a power cut (issue 41): the server syncs each image file and
its folder before the SQLite commit that marks the job succeeded, and deletes the checkpoint only
after that commit. Without the syncs, a rename can reach the disk before the data it names, and
after a power cut the store says succeeded while the image is empty.

No file system here can be cut off without a sync (no device-mapper), so the order is read from
the system calls themselves, with strace, as the server makes them."""

import os
import re
import shutil
import tempfile

import pytest

from conftest import Server, submit_ok

# strace -f pads the thread id to a width ("9802  openat(..."): any run of spaces after it.
CALL = re.compile(r"^(\d+)\s+(\w+)\((.*)\)\s+= (-?\d+)")


def traced_server(caustic_bin, workdir, trace):
    server = Server(caustic_bin, workdir, ["--threads", "1"])
    server.args = ["strace", "-f", "-qq", "-e", "trace=openat,fsync,fdatasync,rename,unlink",
                   "-o", trace, *server.args]
    return server.start(deadline=60)


def calls(trace):
    """(thread, call, arguments, result) of each finished call, unfinished ones joined."""
    pending = {}
    out = []
    with open(trace, encoding="utf-8", errors="replace") as f:
        for line in f:
            line = line.rstrip("\n")
            m = re.match(r"^(\d+)\s+(.*) <unfinished \.\.\.>$", line)
            if m:
                pending[m.group(1)] = m.group(2)
                continue
            m = re.match(r"^(\d+)\s+<\.\.\. \w+ resumed>(.*)$", line)
            if m:
                line = f"{m.group(1)} {pending.pop(m.group(1), '')}{m.group(2)}"
            m = CALL.match(line)
            if m:
                out.append((m.group(1), m.group(2), m.group(3), int(m.group(4))))
    return out


def test_images_are_synced_before_the_commit_that_names_them(caustic_bin):
    if not shutil.which("strace"):
        pytest.fail("strace is not installed (scripts/install-deps.sh installs it)")
    workdir = tempfile.mkdtemp(prefix="caustic-power-")
    trace = os.path.join(workdir, "trace.txt")
    server = traced_server(caustic_bin, workdir, trace)
    try:
        job = submit_ok(server, {"scene": "cornell-box",
                                 "settings": {"width": 32, "height": 32, "spp": 4,
                                              "spp_per_pass": 1}})
        assert server.wait(job["id"], {"succeeded", "failed"})["state"] == "succeeded"
    finally:
        server.stop()
    try:
        folder = os.path.join(server.data, "jobs", job["id"])
        log = calls(trace)
        wal = {r for _, c, a, r in log if c == "openat" and a.split(",")[1].strip().endswith(
            'jobs.sqlite3-wal"')}
        assert wal, "no write-ahead log opened"
        # The thread that finished the job: it deleted the checkpoint.
        unlink = [i for i, (_, c, a, _) in enumerate(log)
                  if c == "unlink" and a == f'"{folder}/checkpoint.bin"']
        assert unlink, "the checkpoint was not deleted"
        tid = log[unlink[-1]][0]
        mine = [(i, c, a, r) for i, (t, c, a, r) in enumerate(log) if t == tid]
        fd_path = {}
        synced = set()  # paths whose fd was fsynced since it was opened
        durable = {}  # image -> its folder was synced after its rename
        commit_after_images = None
        for i, c, a, r in mine:
            if c == "openat" and r >= 0:
                path = a.split(",")[1].strip().strip('"')
                fd_path[r] = path
                synced.discard(path)
            elif c in ("fsync", "fdatasync"):
                fd = int(a)
                if fd in wal:
                    if durable and all(durable.values()) and commit_after_images is None:
                        commit_after_images = i
                    continue
                path = fd_path.get(fd)
                synced.add(path)
                if path == folder:
                    for image in durable:
                        durable[image] = True
            elif c == "rename":
                src, dst = [p.strip().strip('"') for p in a.split('", "')]
                name = os.path.basename(dst)
                if name in ("image.exr", "image.png"):
                    assert src in synced, f"{src} renamed to {name} before it was synced"
                    durable[name] = False
        assert set(durable) == {"image.exr", "image.png"}, durable
        assert all(durable.values()), f"the folder was not synced after a rename: {durable}"
        assert commit_after_images is not None, "no commit after the images were durable"
        assert commit_after_images < unlink[-1], "the checkpoint went before the commit"
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
