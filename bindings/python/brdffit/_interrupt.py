"""Ctrl-C while the library runs a fit.

The library runs a fit without the interpreter, so Python's SIGINT handler
(which raises KeyboardInterrupt) would only run once the fit is over. While
a fit runs in the main thread with the default handler, a watcher thread
reads the interpreter's wakeup pipe and cancels the fit when SIGINT
arrives (and the handler cancels it too when it runs first, in a Python
callback of the fit); once the run is over, ``KeyboardInterrupt`` is raised at a known
point (see :meth:`SigintCancel.raise_if_interrupted`).
"""

import os
import signal
import threading


def _flush_pending():
    """A Python-level call: pending signal handlers run before it returns."""


class SigintCancel:
    """Context manager: SIGINT during the block calls ``cancel()`` at once."""

    def __init__(self, cancel):
        self._cancel = cancel
        self.interrupted = False
        self._active = False

    def _handler(self, signum, frame):
        # Runs when the interpreter next runs Python code in the main
        # thread: in a Python callback of the fit (a model, a policy),
        # which cancels it at once, without waiting for the watcher
        # thread to be scheduled; else after the run.
        self.interrupted = True
        self._cancel()

    def _watch(self, r, old):
        while True:
            data = os.read(r, 64)
            forward = bytes(b for b in data if b != 0)
            if signal.SIGINT in forward:
                self.interrupted = True
                self._cancel()
            if forward and old >= 0:
                try:
                    os.write(old, forward)
                except OSError:
                    pass
            if not data or 0 in data:
                return

    def __enter__(self):
        if (threading.current_thread() is not threading.main_thread()
                or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
            return self
        r, w = os.pipe()
        try:
            os.set_blocking(w, False)
            old = signal.set_wakeup_fd(w)
        except (OSError, ValueError):
            os.close(r)
            os.close(w)
            return self
        self._fds, self._old = (r, w), old
        signal.signal(signal.SIGINT, self._handler)
        self._thread = threading.Thread(target=self._watch, args=(r, old), daemon=True)
        self._thread.start()
        self._active = True
        return self

    def __exit__(self, *exc):
        if not self._active:
            return False
        r, w = self._fds
        signal.set_wakeup_fd(self._old)
        os.write(w, b"\0")
        self._thread.join()
        os.close(r)
        os.close(w)
        _flush_pending()  # a SIGINT still pending runs self._handler now
        signal.signal(signal.SIGINT, signal.default_int_handler)
        self._active = False
        return False

    def raise_if_interrupted(self):
        """Raise KeyboardInterrupt if SIGINT arrived during the block."""
        if self.interrupted:
            raise KeyboardInterrupt
