"""Scale-out fixtures' parts (store/task.h): a throwaway PostgreSQL cluster (tests/support/
postgres.sh), `caustic worker` processes, and a database per test. The tests that use them are
marked `scaleout` and run apart from the rest (CTest label "scaleout")."""

import os
import re
import signal
import subprocess
import tempfile
import time
import uuid

from conftest import ROOT, Process

POSTGRES_SH = os.path.join(ROOT, "tests", "support", "postgres.sh")


class PostgresCluster:
    """One PostgreSQL server on 127.0.0.1 for a test module; stopped and removed by stop(), or by
    postgres.sh's watcher once this Python process is gone."""

    def __init__(self):
        # Under /tmp: the cluster's user (postgres, when run as root) must get through its parents.
        self.folder = tempfile.mkdtemp(prefix="caustic-pg-", dir="/tmp")
        out = subprocess.run(["bash", POSTGRES_SH, "start", self.folder, "--watch",
                              str(os.getpid())], capture_output=True, text=True, timeout=120)
        if out.returncode != 0:
            raise RuntimeError("postgres.sh start failed:\n" + out.stdout + out.stderr)
        self.url = out.stdout.strip().splitlines()[-1]

    def psql(self, sql, database="postgres"):
        url = self.url.rsplit("/", 1)[0] + "/" + database
        out = subprocess.run(["psql", url, "-v", "ON_ERROR_STOP=1", "-Atc", sql],
                             capture_output=True, text=True, timeout=60)
        if out.returncode != 0:
            raise RuntimeError(f"psql {sql!r}: {out.stderr}")
        return out.stdout

    def create_database(self):
        """A new empty database; returns its connection string."""
        name = "t" + uuid.uuid4().hex[:12]
        self.psql(f"CREATE DATABASE {name}")
        return self.url.rsplit("/", 1)[0] + "/" + name

    def restart(self, mode="fast"):
        """Restarts the server on the same port; mode "immediate" stops it as a crash would."""
        out = subprocess.run(["bash", POSTGRES_SH, "restart", self.folder, mode],
                             capture_output=True, text=True, timeout=120)
        if out.returncode != 0:
            raise RuntimeError("postgres.sh restart failed:\n" + out.stdout + out.stderr)

    def down(self):
        """Stops the server, keeping its data (an outage); restart() starts it again."""
        out = subprocess.run(["bash", POSTGRES_SH, "down", self.folder], capture_output=True,
                             text=True, timeout=120)
        if out.returncode != 0:
            raise RuntimeError("postgres.sh down failed:\n" + out.stdout + out.stderr)

    def stop(self):
        subprocess.run(["bash", POSTGRES_SH, "stop", self.folder], capture_output=True,
                       timeout=120)


class Worker(Process):
    """One `caustic worker` process on a store."""

    def __init__(self, binary, store, workdir, *args, prefix=()):
        """`prefix` runs the worker through a command (faketime, to shift its clock)."""
        self.args = [*prefix, binary, "worker", "--store", store, *args]
        self.workdir = workdir
        self.name = "worker-" + uuid.uuid4().hex[:6]
        self.out_path = os.path.join(workdir, self.name + ".out")
        self.log_path = os.path.join(workdir, self.name + ".log")
        self.proc = None

    def start(self, deadline=30):
        with open(self.out_path, "wb") as out, open(self.log_path, "ab") as log:
            self.proc = subprocess.Popen(self.args, stdout=out, stderr=log,
                                         start_new_session=True)
        end = time.monotonic() + deadline
        while True:
            with open(self.out_path, encoding="utf-8", errors="replace") as f:
                if re.search(r"caustic: worker rendering", f.read()):
                    return self
            if self.proc.poll() is not None:
                raise RuntimeError(f"caustic worker exited with {self.proc.returncode}:\n"
                                   + self.log())
            if time.monotonic() > end:
                raise RuntimeError("caustic worker did not start in time:\n" + self.log())
            time.sleep(0.05)

    def kill(self, sig=signal.SIGKILL):
        if self.alive():
            os.killpg(self.proc.pid, sig)
            self.proc.wait(timeout=30)

    def stop(self):
        """SIGTERM: renders in progress give their tasks back."""
        self.terminate(30)
