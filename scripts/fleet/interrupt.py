"""Ctrl-C while an executor runs: noted (its loop stops at the next round and cancels what runs),
not raised in the middle of a poll. restore() puts the previous handler back."""
import signal


class CtrlC:
    def __init__(self):
        self.hit = False
        self._old = signal.signal(signal.SIGINT, self._on)

    def _on(self, signum, frame):
        self.hit = True

    def restore(self):
        signal.signal(signal.SIGINT, self._old)
