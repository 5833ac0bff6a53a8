"""The progress line of a fleet run: drives done / total, failures, running, ETA."""
import sys
import time


class Progress:
    def __init__(self, total, stream=sys.stderr):
        self.total, self.stream = total, stream
        self.tty = stream.isatty()
        self.started = time.monotonic()
        self.last = None

    def line(self, done, failed, running, note=""):
        elapsed = time.monotonic() - self.started
        left = self.total - done
        eta = "?" if done == 0 else _clock(elapsed / done * left)
        text = (f"meter-fleet: {done}/{self.total} done, {failed} failed, {running} running, "
                f"elapsed {_clock(elapsed)}, ETA {eta}" + (f" ({note})" if note else ""))
        return text

    def show(self, done, failed, running, note=""):
        text = self.line(done, failed, running, note)
        key = (done, failed, running, note)
        if self.tty:
            self.stream.write("\r\033[K" + text)
        elif key != self.last:  # a log file gets one line per change, not a line per poll
            self.stream.write(text + "\n")
        self.stream.flush()
        self.last = key

    def finish(self):
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()


def _clock(seconds):
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"
