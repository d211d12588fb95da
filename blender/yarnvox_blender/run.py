"""One `yarnvox voxelize` run in the background: its progress lines read on
a thread of their own, so Blender's interface keeps going; cancel() stops it
as Ctrl-C does (at a region boundary, nothing written)."""

import queue
import re
import signal
import subprocess
import threading

PROGRESS = re.compile(r"^progress: (\S+) (\d+)/(\d+)")


class VoxelizeRun:
    def __init__(self, executable, words):
        self.process = subprocess.Popen([executable, "voxelize", "--progress-lines", *words], stdout=subprocess.DEVNULL,
                                        stderr=subprocess.PIPE, text=True, start_new_session=True)
        self.fraction = 0.0
        self.last_line = ""
        self.lines = queue.Queue()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        for line in self.process.stderr:
            self.lines.put(line.rstrip("\n"))

    def poll(self):
        """None while it runs, else its exit status; updates fraction and last_line."""
        while True:
            try:
                line = self.lines.get_nowait()
            except queue.Empty:
                break
            m = PROGRESS.match(line)
            if m:
                self.fraction = int(m.group(2)) / max(1, int(m.group(3)))
            elif line.strip():
                self.last_line = line
        code = self.process.poll()
        if code is not None:
            self.reader.join()
            if not self.lines.empty():
                return self.poll()
        return code

    def wait(self):
        self.process.wait()
        self.reader.join()
        return self.poll()

    def cancel(self):
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
        return self.wait()

    def error(self):
        """The one line yarnvox said why it failed."""
        line = self.last_line
        for prefix in ("yarnvox: error: ", "yarnvox: "):
            if line.startswith(prefix):
                line = line[len(prefix):]
                break
        return line[: -len(" (see --help)")] if line.endswith(" (see --help)") else line
