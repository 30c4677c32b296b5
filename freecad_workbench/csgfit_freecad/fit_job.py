"""A fit in a worker thread, polled from the GUI thread (needs neither FreeCAD nor Qt)."""

import threading
import time


class FitJob:
    """One fit in a worker thread. Poll done(); then read result or error.

    fit: the csgfit function to run (fit_image, fit_mesh); it is called as
    fit(source, progress=..., cancel=..., **options)."""

    def __init__(self, csgfit, fit, source, options):
        self.token = csgfit.CancelToken()
        self.progress = None  # latest csgfit.FitProgress (written by the solver thread)
        self.result = None
        self.error = None
        self.options = options
        self.started = None  # time.monotonic() at start()
        self._fit = fit
        self._source = source
        self._thread = threading.Thread(target=self._run, name="csgfit-fit", daemon=True)

    def start(self):
        self.started = time.monotonic()
        self._thread.start()

    def _on_progress(self, p):
        self.progress = p
        return True

    def _run(self):
        try:
            self.result = self._fit(self._source, progress=self._on_progress, cancel=self.token,
                                    **self.options)
        except Exception as e:  # shown in the panel, never a traceback dialog
            self.error = e

    def done(self):
        return not self._thread.is_alive()

    def cancel(self, wait=0.0):
        self.token.cancel()
        if wait > 0:
            self._thread.join(wait)
