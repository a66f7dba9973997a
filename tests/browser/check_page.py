#!/usr/bin/env python3
"""Opens a local HTML page in headless Chromium and checks it: no console error, no uncaught
exception, no failed load, every <img> decoded (naturalWidth > 0; lazy ones are loaded first), every
--eval expression true; writes a screenshot.

    tests/browser/check_page.py PAGE.html SHOT.png [--size WxH] [--timeout S] [--eval JS]...

--eval JS runs after the load (in the order given, the screenshot after the last): an expression
whose value is not `true` (or that throws) is a failure, its value named; one that clicks something
and then yields `true` (`el.click(), true`) acts on the page.

Exit 0 when the page passes, 1 when a check fails (each failure one line on stderr), 2 on usage
errors, 3 when Chromium could not be started or did not answer in time. It talks to Chromium
through the DevTools protocol over a pipe (--remote-debugging-pipe): no port, no network, only
python3's standard library and Debian's chromium package.
"""
import argparse
import base64
import json
import os
import pathlib
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time

# How long the page may stay quiet after its load event before it is judged: errors of scripts
# that run later than that are not seen.
SETTLE_SECONDS = 0.5

# Lazy images (loading="lazy", as in a batch's summary.html) load only once scrolled near: made
# eager, so that every <img> of a long page is loaded and judged; resolves when all have loaded or
# failed, to how many were lazy.
LOAD_LAZY_JS = """Promise.all(Array.from(document.images, img => {
  if (img.loading === 'lazy') { img.loading = 'eager'; img.dataset.wasLazy = '1'; }
  return img.complete ? null : new Promise(done => {
    img.addEventListener('load', done); img.addEventListener('error', done); });
})).then(() => document.querySelectorAll('img[data-was-lazy]').length)"""

IMAGES_JS = """JSON.stringify(Array.from(document.images, img => ({
  src: img.currentSrc || img.src, complete: img.complete, width: img.naturalWidth})))"""


class Browser:
    """Chromium with the DevTools protocol on fds 3 (commands in) and 4 (replies and events out)."""

    def __init__(self, args, deadline, log):
        self.deadline = deadline
        cmd_read, self.cmd_write = os.pipe()
        self.out_read, out_write = os.pipe()
        # The child's fds 3 and 4 must be exactly these pipe ends (copied first, in case either
        # already is 3 or 4); close_fds=False, as subprocess would close them after preexec_fn.
        def child_fds():
            ends = os.dup(cmd_read), os.dup(out_write)
            os.dup2(ends[0], 3)
            os.dup2(ends[1], 4)
        self.proc = subprocess.Popen(args, close_fds=False, preexec_fn=child_fds,
                                     start_new_session=True, stdin=subprocess.DEVNULL,
                                     stdout=log, stderr=log)
        os.close(cmd_read)
        os.close(out_write)
        self.buffer = b""
        self.next_id = 0
        self.events = []

    def send(self, method, params=None, session=None):
        """Sends a command and returns its result; events that arrive meanwhile are kept."""
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.cmd_write, json.dumps(message).encode() + b"\0")
        while True:
            reply = self.receive()
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error'].get('message')}")
                return reply.get("result", {})
            self.events.append(reply)

    def receive(self, until=None):
        """The next message; None if none came before `until` (default: the overall deadline)."""
        until = until or self.deadline
        while b"\0" not in self.buffer:
            left = until - time.monotonic()
            if left <= 0:
                if until < self.deadline:
                    return None
                raise TimeoutError("Chromium did not answer in time")
            ready, _, _ = select.select([self.out_read], [], [], left)
            if ready:
                chunk = os.read(self.out_read, 1 << 20)
                if not chunk:
                    raise TimeoutError("Chromium closed the DevTools pipe")
                self.buffer += chunk
        message, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(message)

    def wait_for(self, method):
        while not any(e.get("method") == method for e in self.events):
            self.events.append(self.receive())

    def drain(self, seconds):
        until = time.monotonic() + seconds
        while (message := self.receive(until)) is not None:
            self.events.append(message)

    def close(self):
        """Asks Chromium to quit, then ends its process group (it and its helpers) if it did not."""
        try:
            os.write(self.cmd_write, json.dumps({"id": 0, "method": "Browser.close"}).encode() + b"\0")
            self.proc.wait(timeout=10)
        except (OSError, subprocess.TimeoutExpired):
            pass
        for sig in (signal.SIGTERM, signal.SIGKILL):
            try:
                os.killpg(self.proc.pid, sig)
            except ProcessLookupError:
                break
            try:
                self.proc.wait(timeout=5)
            except subprocess.TimeoutExpired:
                continue
        os.close(self.cmd_write)
        os.close(self.out_read)


def failures_in(events):
    """One line per console error, uncaught exception or failed load among the events."""
    lines = []
    for event in events:
        method, params = event.get("method"), event.get("params", {})
        if method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in params["args"])
            lines.append(f"console.{params['type']}: {text}")
        elif method == "Runtime.exceptionThrown":
            details = params["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            lines.append(f"uncaught exception: {text}")
        elif method == "Log.entryAdded" and params["entry"]["level"] == "error":
            entry = params["entry"]
            lines.append(f"{entry['source']} error: {entry['text']} {entry.get('url', '')}".rstrip())
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("page", type=pathlib.Path, help="a local HTML file")
    parser.add_argument("shot", type=pathlib.Path, help="the PNG screenshot to write")
    parser.add_argument("--size", default="1280x800", help="the window, WxH (default 1280x800)")
    parser.add_argument("--timeout", type=float, default=60,
                        help="seconds for the whole check (default 60)")
    parser.add_argument("--eval", action="append", default=[], metavar="JS", dest="evals",
                        help="after the load, an expression that must be true (repeatable)")
    args = parser.parse_args()
    if not args.page.is_file():
        print(f"error: {args.page}: no such file", file=sys.stderr)
        return 2
    width, _, height = args.size.partition("x")
    if not (width.isdigit() and height.isdigit()):
        print(f"error: --size {args.size}: expected WxH", file=sys.stderr)
        return 2
    chromium = shutil.which("chromium")
    if not chromium:
        print("error: chromium not found (UNTANGLE_BROWSER_TEST=1 bash scripts/setup.sh)",
              file=sys.stderr)
        return 3

    profile = tempfile.mkdtemp(prefix="untangle-chromium.")
    log_path = pathlib.Path(profile, "chromium.log")
    log = open(log_path, "wb")  # a file, not a pipe nobody reads that could fill and block Chromium
    browser = Browser([chromium, "--headless=new", "--no-sandbox", "--disable-gpu",
                       "--disable-dev-shm-usage", "--no-first-run", "--no-default-browser-check",
                       "--disable-extensions", "--disable-background-networking",
                       f"--user-data-dir={profile}", f"--window-size={width},{height}",
                       "--remote-debugging-pipe", "about:blank"],
                      time.monotonic() + args.timeout, log)
    try:
        target = browser.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = browser.send("Target.attachToTarget",
                               {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            browser.send(f"{domain}.enable", session=session)
        browser.events.clear()  # what about:blank said is not the page's
        browser.send("Emulation.setDeviceMetricsOverride", {"width": int(width), "height": int(height),
                     "deviceScaleFactor": 1, "mobile": False}, session=session)
        browser.send("Page.navigate", {"url": args.page.resolve().as_uri()}, session=session)
        browser.wait_for("Page.loadEventFired")
        browser.drain(SETTLE_SECONDS)
        failures = []
        lazy = browser.send("Runtime.evaluate", {"expression": LOAD_LAZY_JS, "awaitPromise": True,
                            "returnByValue": True}, session=session)["result"]["value"]
        images = json.loads(browser.send("Runtime.evaluate", {"expression": IMAGES_JS,
                            "returnByValue": True}, session=session)["result"]["value"])
        for image in images:
            if not image["complete"] or image["width"] <= 0:
                failures.append(f"image not decoded (naturalWidth {image['width']}): {image['src']}")
        for expression in args.evals:
            reply = browser.send("Runtime.evaluate", {"expression": expression, "returnByValue": True},
                                 session=session)
            if "exceptionDetails" in reply:
                details = reply["exceptionDetails"]
                text = details.get("exception", {}).get("description") or details.get("text")
                failures.append(f"--eval {expression}: threw {text}")
            elif reply["result"].get("value") is not True:
                value = reply["result"].get("value", reply["result"].get("description"))
                failures.append(f"--eval {expression}: is {json.dumps(value)}, not true")
        if args.evals:
            browser.drain(SETTLE_SECONDS)  # what the expressions set off (a click's handler)
        failures = failures_in(browser.events) + failures
        shot = browser.send("Page.captureScreenshot", {"format": "png", "captureBeyondViewport": True},
                            session=session)
        args.shot.write_bytes(base64.b64decode(shot["data"]))
    except (TimeoutError, RuntimeError) as error:
        browser.close()
        log.close()
        output = log_path.read_bytes()[-2000:].decode(errors="replace")
        print(f"error: {args.page}: {error}\n{output}", file=sys.stderr)
        shutil.rmtree(profile, ignore_errors=True)
        return 3
    browser.close()
    log.close()
    shutil.rmtree(profile, ignore_errors=True)
    for line in failures:
        print(f"{args.page}: {line}", file=sys.stderr)
    print(f"{args.page}: {len(images)} images ({lazy} lazy), {len(failures)} failures; wrote {args.shot}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
