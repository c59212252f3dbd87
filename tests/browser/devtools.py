"""A headless Chromium driven through its DevTools protocol over a pipe (--remote-debugging-pipe), with Python's
standard library only: no WebSocket, no port, no download.

The protocol (https://chromedevtools.github.io/devtools-protocol/): the browser reads commands from its file
descriptor 3 and writes replies and events to its descriptor 4, each message one JSON object followed by a NUL byte.
A command is {"id", "method", "params"[, "sessionId"]}; its reply carries the same id, with "result" or "error".
A page is reached through a session: Target.createTarget, then Target.attachToTarget with flatten=true.

The browser is started without a shell (subprocess with an argument vector); its own messages go to a log file.
"""

import base64
import fcntl
import json
import os
import select
import shutil
import subprocess
import tempfile
import time

# Debian's chromium package: the browser itself (the /usr/bin/chromium launcher is a shell script around it).
DEBIAN_CHROMIUM = "/usr/lib/chromium/chromium"


def find_chromium(explicit=None):
    """The browser to run: `explicit`, else Debian's binary, else `chromium` or `chromium-browser` on PATH; None if
    there is none."""
    if explicit:
        return explicit if os.access(explicit, os.X_OK) else None
    if os.access(DEBIAN_CHROMIUM, os.X_OK):
        return DEBIAN_CHROMIUM
    return shutil.which("chromium") or shutil.which("chromium-browser")


class ProtocolError(RuntimeError):
    pass


class Browser:
    """One headless Chromium. Use as a context manager; `timeout` bounds every wait, in seconds."""

    def __init__(self, executable, timeout=60.0, width=1200, height=900):
        self.timeout = timeout
        self.events = []  # every event received, as (sessionId or None, method, params)
        self._next_id = 0
        self._buffer = b""
        self._profile = tempfile.mkdtemp(prefix="mb_chromium_")
        self.log_path = os.path.join(self._profile, "chromium.log")
        # The pipe's ends on descriptors >= 10 (close-on-exec), moved to 3 and 4 in the child only.
        command_read, command_write = os.pipe()
        reply_read, reply_write = os.pipe()
        high = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in (command_read, command_write, reply_read,
                                                                         reply_write)]
        for fd in (command_read, command_write, reply_read, reply_write):
            os.close(fd)
        child_read, self._write_fd, self._read_fd, child_write = high

        def to_3_and_4():  # in the child, before exec: dup2 leaves 3 and 4 inheritable
            os.dup2(child_read, 3)
            os.dup2(child_write, 4)

        args = [executable, "--headless=new", "--no-sandbox", "--disable-gpu", "--remote-debugging-pipe",
                "--no-first-run", "--no-default-browser-check", "--disable-extensions", "--mute-audio",
                "--hide-scrollbars", f"--window-size={width},{height}", f"--user-data-dir={self._profile}",
                "about:blank"]
        self._log = open(self.log_path, "wb")
        self._process = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=self._log, stderr=self._log,
                                         close_fds=False, preexec_fn=to_3_and_4)
        os.close(child_read)
        os.close(child_write)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        if self._process.poll() is None:
            try:
                self._send("Browser.close", {})
            except (OSError, ProtocolError):
                pass
            try:
                self._process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self._process.kill()  # the browser this object started, by its own handle
                self._process.wait()
        for fd in (self._write_fd, self._read_fd):
            try:
                os.close(fd)
            except OSError:
                pass
        self._log.close()
        shutil.rmtree(self._profile, ignore_errors=True)

    def log_tail(self, lines=20):
        """The browser's last messages (to explain a failure)."""
        try:
            with open(self.log_path, "rb") as f:
                return b"\n".join(f.read().splitlines()[-lines:]).decode("utf-8", "replace")
        except OSError:
            return ""

    def _send(self, method, params, session=None):
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = session
        data = json.dumps(message).encode() + b"\0"
        while data:
            written = os.write(self._write_fd, data)
            data = data[written:]
        return self._next_id

    def _receive(self, deadline):
        """The next message, or ProtocolError when the deadline passes or the browser ends."""
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise ProtocolError(f"no answer from chromium within {self.timeout:.0f} s")
            ready, _, _ = select.select([self._read_fd], [], [], left)
            if not ready:
                continue
            chunk = os.read(self._read_fd, 1 << 20)
            if not chunk:
                raise ProtocolError(f"chromium ended (exit {self._process.poll()}): {self.log_tail()}")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method, params=None, session=None):
        """Sends a command and returns its result; events that arrive meanwhile are kept in `events`."""
        wanted = self._send(method, params or {}, session)
        deadline = time.monotonic() + self.timeout
        while True:
            message = self._receive(deadline)
            if message.get("id") == wanted:
                if "error" in message:
                    raise ProtocolError(f"{method}: {message['error'].get('message')}")
                return message.get("result", {})
            if "method" in message:
                self.events.append((message.get("sessionId"), message["method"], message.get("params", {})))

    def wait_for_event(self, method, session, start=0):
        """Waits until an event `method` of `session` is among events[start:]; returns its params."""
        deadline = time.monotonic() + self.timeout
        while True:
            for s, m, p in self.events[start:]:
                if s == session and m == method:
                    return p
            message = self._receive(deadline)
            if "method" in message:
                self.events.append((message.get("sessionId"), message["method"], message.get("params", {})))

    def open_page(self, url, width=1200, height=900):
        """A new tab showing `url`, loaded (its load event fired), with the console and the log recorded from
        before the page's first script. Returns the page's session id."""
        target = self.call("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime", "Log", "Page"):
            self.call(f"{domain}.enable", {}, session)
        self.call("Emulation.setDeviceMetricsOverride",
                  {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False}, session)
        start = len(self.events)
        self.call("Page.navigate", {"url": url}, session)
        self.wait_for_event("Page.loadEventFired", session, start)
        return session

    def evaluate(self, session, expression):
        """The value of a JavaScript expression in the page (a promise is awaited). Raises ProtocolError with the
        exception's text if it throws."""
        result = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True,
                                                "awaitPromise": True}, session)
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            raise ProtocolError("script failed: " + details.get("exception", {}).get("description", details["text"]))
        return result["result"].get("value")

    def page_errors(self, session):
        """What the page reported as an error: uncaught exceptions, console.error/assert calls and the browser's own
        error-level log entries (a resource that failed to load, a blocked script), as text lines."""
        errors = []
        for s, method, p in self.events:
            if s != session:
                continue
            if method == "Runtime.exceptionThrown":
                d = p["exceptionDetails"]
                errors.append("uncaught exception: " + d.get("exception", {}).get("description", d.get("text", "")))
            elif method == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                words = [str(a.get("value", a.get("description", ""))) for a in p.get("args", [])]
                errors.append(f"console.{p['type']}: " + " ".join(words))
            elif method == "Log.entryAdded" and p["entry"].get("level") == "error":
                e = p["entry"]
                errors.append(f"browser log ({e.get('source')}): {e.get('text')} {e.get('url', '')}".rstrip())
        return errors

    def screenshot(self, session, path, scale=1.0):
        """Writes what the page's viewport shows to `path` (PNG), its pixels `scale` times the page's (0.8: a
        1200 × 900 viewport becomes a 960 × 720 picture)."""
        view = self.evaluate(session, "[window.scrollX, window.scrollY, window.innerWidth, window.innerHeight]")
        clip = {"x": view[0], "y": view[1], "width": view[2], "height": view[3], "scale": scale}
        data = self.call("Page.captureScreenshot", {"format": "png", "clip": clip}, session)["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))
