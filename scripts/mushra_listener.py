#!/usr/bin/python3
"""A scripted listener for room_reverb's MUSHRA test page.

Completes a test made by `room_reverb mushra make` in headless Chromium through the page's
real controls, as a person would: types the listener's name, presses Start, and on every
page clicks each letter's play button, moves each slider with the mouse and the keyboard
to the score it chose, and presses Next; then keeps the CSV the page offers as a download.
It checks on the way that Next stays disabled until every stimulus has been played and
rated. The scores are given per condition (--scores reference=5,...) and, for conditions
not named, drawn from --seed per page and condition, so a test can compare the CSV with
what was given.

    mushra_listener.py DIR|URL --out RESULTS.csv [--name NAME] [--scores C=S,...]
                       [--seed N] [--given GIVEN.json] [--timeout S]

DIR opens DIR/index.html from the file system; a URL (http://127.0.0.1:PORT/) opens the
page served by `room_reverb mushra serve`, to which the page then also posts its results.
Exit status: 0 when the test was completed and the CSV saved, 1 when the page misbehaved,
2 for bad arguments or a missing browser (the message says which).

Chromium is driven over the DevTools protocol on a pipe (--remote-debugging-pipe: it
reads commands from fd 3 and writes answers to fd 4, one JSON message per NUL-terminated
record), so nothing listens on a port and only the standard library is needed. Without
a sound card, Chromium plays into a fake audio output whose clock still runs; the page's
AudioContext is created on the Start click, which is a user gesture, and
--autoplay-policy=no-user-gesture-required makes sure a context is never held suspended.
"""

import argparse
import base64
import fcntl
import hashlib
import json
import os
import select
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.parse


class PageError(Exception):
    """The page did not behave as the test page must."""


def fail_usage(message):
    print("mushra_listener: " + message, file=sys.stderr)
    sys.exit(2)


def find_chromium(explicit):
    if explicit:
        if shutil.which(explicit):
            return shutil.which(explicit)
        fail_usage(explicit + ": no such browser")
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    fail_usage("chromium is not installed (Debian: apt-get install chromium; scripts/setup installs it)")


class Browser:
    """One headless Chromium and the DevTools protocol over its pipe."""

    def __init__(self, executable, flags, log_path):
        self.profile = tempfile.mkdtemp(prefix="mushra_listener_profile_")
        to_browser_read, self.to_browser = os.pipe()
        self.from_browser, from_browser_write = os.pipe()
        # Chromium expects the pipe on fds 3 and 4. os.pipe() may itself have returned 3 or
        # 4, so the child's ends are first moved above them (close-on-exec, like every fd
        # Python opens), then put in place in the child, where dup2 makes them inheritable.
        child_read = fcntl.fcntl(to_browser_read, fcntl.F_DUPFD_CLOEXEC, 10)
        child_write = fcntl.fcntl(from_browser_write, fcntl.F_DUPFD_CLOEXEC, 10)
        os.close(to_browser_read)
        os.close(from_browser_write)

        def place_pipe():
            os.dup2(child_read, 3)
            os.dup2(child_write, 4)

        command = [executable, "--headless=new", "--remote-debugging-pipe", "--user-data-dir=" + self.profile] + flags
        self.log = open(log_path, "w") if log_path else subprocess.DEVNULL
        # close_fds=False: it would close fds 3 and 4 after place_pipe() ran.
        self.process = subprocess.Popen(command + ["about:blank"], stdin=subprocess.DEVNULL, stdout=self.log,
                                        stderr=self.log, preexec_fn=place_pipe, close_fds=False)
        os.close(child_read)
        os.close(child_write)
        self.buffer = b""
        self.next_id = 0
        self.events = []
        self.session = None

    def send(self, method, params=None, session=True):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            message["sessionId"] = self.session
        data = json.dumps(message).encode() + b"\0"
        while data:
            written = os.write(self.to_browser, data)
            data = data[written:]
        return self.next_id

    def _read(self, deadline):
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            return False
        ready, _, _ = select.select([self.from_browser], [], [], remaining)
        if not ready:
            return False
        chunk = os.read(self.from_browser, 1 << 20)
        if not chunk:
            raise PageError("the browser closed the DevTools pipe (did it crash? see its log)")
        self.buffer += chunk
        return True

    def _messages(self):
        while b"\0" in self.buffer:
            record, self.buffer = self.buffer.split(b"\0", 1)
            yield json.loads(record)

    def call(self, method, params=None, session=True, timeout=30.0):
        wanted = self.send(method, params, session)
        deadline = time.monotonic() + timeout
        while True:
            for message in self._messages():
                if message.get("id") == wanted:
                    if "error" in message:
                        raise PageError(method + ": " + message["error"].get("message", str(message["error"])))
                    return message.get("result", {})
                if "method" in message:
                    self.events.append(message)
            if not self._read(deadline):
                raise PageError(method + ": no answer from the browser in %.0f s" % timeout)

    def pump(self, seconds):
        """Collects the events that arrive within `seconds`."""
        deadline = time.monotonic() + seconds
        while True:
            for message in self._messages():
                if "method" in message:
                    self.events.append(message)
            if not self._read(deadline):
                return

    def wait_event(self, method, timeout):
        deadline = time.monotonic() + timeout
        while True:
            for index, event in enumerate(self.events):
                if event["method"] == method:
                    return self.events.pop(index)
            if time.monotonic() > deadline:
                raise PageError("no %s within %.0f s" % (method, timeout))
            self.pump(0.05)

    def close(self):
        try:
            if self.process.poll() is None:
                self.send("Browser.close", session=False)
                self.process.wait(timeout=10)
        except (OSError, subprocess.TimeoutExpired):
            self.process.kill()
            self.process.wait()
        for fd in (self.to_browser, self.from_browser):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self.profile, ignore_errors=True)


class Page:
    """The test page in one tab: evaluation, waiting, and real mouse and keyboard input."""

    def __init__(self, browser):
        self.browser = browser

    def evaluate(self, expression):
        result = self.browser.call("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise PageError("in the page: " + str(text))
        return result.get("result", {}).get("value")

    def check_errors(self):
        for event in self.browser.events:
            if event["method"] == "Runtime.exceptionThrown":
                details = event["params"]["exceptionDetails"]
                text = details.get("exception", {}).get("description") or details.get("text")
                raise PageError("the page threw: " + str(text))
        fatal = self.evaluate("(() => { const f = document.getElementById('fatal');"
                              " return f && !f.hidden ? f.textContent : null; })()")
        if fatal:
            raise PageError("the page says: " + fatal)

    def wait_for(self, expression, what, timeout=20.0):
        deadline = time.monotonic() + timeout
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            self.check_errors()
            if time.monotonic() > deadline:
                raise PageError("timed out waiting for " + what)
            self.browser.pump(0.05)

    def center_of(self, selector):
        box = self.evaluate("""(() => {
            const e = document.querySelector(%s);
            if (!e) return null;
            e.scrollIntoView({block: "center", inline: "center"});
            const r = e.getBoundingClientRect();
            return {x: r.left + r.width / 2, y: r.top + r.height / 2, disabled: !!e.disabled,
                    visible: r.width > 0 && r.height > 0};
        })()""" % json.dumps(selector))
        if not box or not box["visible"]:
            raise PageError(selector + ": not on the page")
        return box

    def click(self, selector, expect_enabled=True):
        box = self.center_of(selector)
        if expect_enabled and box["disabled"]:
            raise PageError(selector + ": disabled when it should be usable")
        for kind in ("mouseMoved", "mousePressed", "mouseReleased"):
            params = {"type": kind, "x": box["x"], "y": box["y"], "button": "left", "buttons": 1,
                      "clickCount": 1}
            if kind == "mouseMoved":
                params.update(button="none", buttons=0)
            self.browser.call("Input.dispatchMouseEvent", params)

    KEYS = {
        "ArrowUp": ("ArrowUp", 38, None), "ArrowDown": ("ArrowDown", 40, None), "Home": ("Home", 36, None),
        "End": ("End", 35, None), " ": ("Space", 32, " "), "Enter": ("Enter", 13, "\r"),
    }

    def press(self, key):
        if key in self.KEYS:
            code, virtual_key, text = self.KEYS[key]
        elif len(key) == 1 and key.isalnum():
            code = ("Digit" if key.isdigit() else "Key") + key.upper()
            virtual_key, text = ord(key.upper()), key
        else:
            raise ValueError("no key code for " + repr(key))
        down = {"type": "keyDown", "key": key, "code": code, "windowsVirtualKeyCode": virtual_key}
        if text:
            down["text"] = text
        self.browser.call("Input.dispatchKeyEvent", down)
        self.browser.call("Input.dispatchKeyEvent",
                          {"type": "keyUp", "key": key, "code": code, "windowsVirtualKeyCode": virtual_key})

    def type_text(self, text):
        for char in text:
            down = {"type": "keyDown", "key": char, "text": char}
            self.browser.call("Input.dispatchKeyEvent", down)
            self.browser.call("Input.dispatchKeyEvent", {"type": "keyUp", "key": char})

    def inspect(self):
        return self.evaluate("window.mushraInspect()")


def parse_scores(text):
    scores = {}
    for item in filter(None, (text or "").split(",")):
        name, _, value = item.partition("=")
        try:
            scores[name.strip()] = float(value)
        except ValueError:
            fail_usage("--scores: '%s' is not CONDITION=SCORE" % item)
    return scores


def chosen_score(scores, seed, page_id, condition, scale):
    """The score for a condition on a page: as given, else drawn from the seed (inside the
    scale's ends, so that the extremes stay with the anchors the caller named)."""
    low, high, step = scale["min"], scale["max"], scale["step"]
    if condition in scores:
        value = scores[condition]
        if not low <= value <= high:
            fail_usage("--scores: %s=%g is outside the scale %g..%g" % (condition, value, low, high))
        return value
    steps = int(round((high - low) / step))
    digest = hashlib.sha256(("%d|%s|%s" % (seed, page_id, condition)).encode()).digest()
    inner = max(steps - 1, 1)
    return low + step * (1 + int.from_bytes(digest[:4], "little") % inner) if steps > 1 else low


def set_slider(page, index, score, scale):
    """Moves slider `index` to `score` as a person could: a click on the slider (which
    focuses it and moves it under the pointer), End and Home (so that it surely moved),
    then the arrow key once per step."""
    selector = "#score-%d" % index
    page.click(selector)
    page.press("End")
    page.press("Home")
    for _ in range(int(round((score - scale["min"]) / scale["step"]))):
        page.press("ArrowUp")
    value = page.evaluate("Number(document.querySelector(%s).value)" % json.dumps(selector))
    if abs(value - score) > 1e-9:
        raise PageError("%s shows %g after setting %g" % (selector, value, score))


def check_loop(page):
    """A click in the middle of the loop-end slider ends the loop half way, Home pulls the
    end down to the shortest loop the page allows; playing on for longer than the loop, the
    position must stay inside it. "Whole excerpt" undoes it."""
    if not page.inspect()["page"]["playing"]:
        page.click("#play")
    page.click("#loop-end")
    start, end = page.inspect()["page"]["loop"]
    duration = page.inspect()["page"]["duration"]
    if not 0.25 * duration < end < 0.75 * duration:
        raise PageError("a click on the middle of the loop-end slider set the loop to %.2f..%.2f s of %.2f s"
                        % (start, end, duration))
    page.press("Home")
    start, end = page.inspect()["page"]["loop"]
    if not 0.1 < end - start < 0.5:
        raise PageError("Home on the loop-end slider left the loop at %.2f..%.2f s" % (start, end))
    clock = page.inspect()["audio"]["time"]
    positions = []
    while page.inspect()["audio"]["time"] - clock < 1.5 * (end - start) and len(positions) < 200:
        page.browser.pump(0.03)
        positions.append(page.inspect()["page"]["position"])
    if any(not start <= p <= end + 0.01 for p in positions):
        raise PageError("the playback left the loop %.2f..%.2f s: %s" % (start, end, positions))
    if max(positions) - min(positions) < 0.5 * (end - start):
        raise PageError("the playback position did not move through the loop (%s)" % positions)
    page.click("#loop-reset")
    if page.inspect()["page"]["loop"][1] < duration - 1e-6:
        raise PageError("'Whole excerpt' did not reset the loop")


def next_disabled(page):
    return page.evaluate("document.getElementById('next').disabled")


def complete_page(page, args, scores, given, audio_report, first_page):
    info = page.inspect()
    current = info["page"]
    scale = info["scale"]
    stimuli = current["stimuli"]
    if not next_disabled(page):
        raise PageError(current["id"] + ": Next is enabled before anything was played")
    # Aim only once the page has settled (the panorama loaded), as a person would.
    page.wait_for("Array.from(document.images).every(i => i.hidden || i.complete)", "the page's images")
    if first_page:
        # The shown reference plays but is not rated, and hearing it does not count as
        # having played its hidden letter.
        if page.evaluate("document.querySelectorAll('#references button').length") > 0:
            page.click("#references button")
            page.browser.pump(0.15)
            if any(s["played"] for s in page.inspect()["page"]["stimuli"]):
                raise PageError("playing the shown reference marked a letter as played")
        check_loop(page)
        page.press(" ")  # stop
        if page.inspect()["page"]["playing"]:
            raise PageError("Space did not stop the playback")
    for index, stimulus in enumerate(stimuli):
        page.click("#stimulus-%d" % index)
        before = page.inspect()["audio"]
        page.browser.pump(0.12)
        after = page.inspect()
        audio_report.append((before["time"], after["audio"]["time"], after["audio"]["state"],
                             after["audio"]["sample_rate_hz"]))
        # A busy machine may take longer than the pump above to run the click's handler.
        page.wait_for("window.mushraInspect().page.stimuli[%d].played" % index,
                      "%s: letter %s to be marked as played after its click" % (current["id"], stimulus["letter"]),
                      timeout=5.0)
        if not after["page"]["playing"]:
            raise PageError("%s: the click on %s did not start the playback" % (current["id"], stimulus["letter"]))
        score = chosen_score(scores, args.seed, current["id"], stimulus["condition"], scale)
        if index == len(stimuli) - 1 and not next_disabled(page):
            raise PageError(current["id"] + ": Next is enabled before the last stimulus was rated")
        set_slider(page, index, score, scale)
        given.append({"page": current["id"], "condition": stimulus["condition"], "letter": stimulus["letter"],
                      "score": score})
    if not first_page:
        # The keyboard: a digit plays a letter, Space stops.
        page.press("1")
        if page.inspect()["page"]["playing"] is not True:
            raise PageError("key 1 did not play letter A")
        page.press(" ")
    if next_disabled(page):
        raise PageError(current["id"] + ": Next still disabled with every stimulus played and rated")
    if first_page and args.screenshot:
        page.evaluate("window.scrollTo(0, 0)")
        shot = page.browser.call("Page.captureScreenshot", {"format": "png", "captureBeyondViewport": True})
        with open(args.screenshot, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
    page.click("#next")


def run(args):
    executable = find_chromium(args.chromium)
    if args.target.startswith("http://") or args.target.startswith("https://"):
        url = args.target
    else:
        index = os.path.join(os.path.abspath(args.target), "index.html")
        if not os.path.isfile(index):
            fail_usage(args.target + ": no index.html (make the test with room_reverb mushra make)")
        url = "file://" + urllib.parse.quote(index)
    scores = parse_scores(args.scores)
    downloads = tempfile.mkdtemp(prefix="mushra_listener_downloads_")
    flags = ["--no-sandbox", "--disable-gpu", "--no-first-run", "--no-default-browser-check",
             "--disable-extensions", "--disable-background-networking", "--disable-component-update",
             "--disable-sync", "--window-size=1280,1400"]
    if not args.no_autoplay_flag:
        flags.append("--autoplay-policy=no-user-gesture-required")
    started = time.monotonic()
    browser = Browser(executable, flags, args.browser_log)
    given, audio_report, ready_s = [], [], []
    try:
        target = browser.call("Target.createTarget", {"url": "about:blank"}, session=False)
        attached = browser.call("Target.attachToTarget", {"targetId": target["targetId"], "flatten": True},
                                session=False)
        browser.session = attached["sessionId"]
        browser.call("Page.enable")
        browser.call("Runtime.enable")
        browser.call("Browser.setDownloadBehavior", {"behavior": "allow", "downloadPath": downloads,
                                                     "eventsEnabled": True}, session=False)
        browser.call("Page.navigate", {"url": url})
        browser.wait_event("Page.loadEventFired", args.timeout)
        page = Page(browser)
        if not page.evaluate("!!document.getElementById('fatal')"):
            raise PageError("%s: not a room_reverb MUSHRA test page (the browser shows '%s')"
                            % (url, page.evaluate("document.title || document.body.innerText.slice(0, 80)")))
        page.wait_for("document.body.dataset.loaded === 'true' || !document.getElementById('fatal').hidden",
                      "the page to load")
        page.check_errors()
        page.click("#listener-name", expect_enabled=False)
        page.type_text(args.name)
        page.click("#start")
        pages = page.wait_for("window.mushraInspect().pages", "the first page")
        for number in range(pages):
            page.wait_for("(() => { const i = window.mushraInspect(); return i.position === %d && i.page && "
                          "i.page.ready; })()" % number, "page %d to be ready" % (number + 1), args.timeout)
            ready_s.append(page.inspect()["page"]["ready_after_s"])
            complete_page(page, args, scores, given, audio_report, number == 0)
        page.wait_for("document.body.dataset.finished === 'true'", "the end of the test")
        shown = page.evaluate("document.getElementById('results-csv').value")
        done = browser.wait_event("Browser.downloadWillBegin", args.timeout)["params"]
        while True:
            progress = browser.wait_event("Browser.downloadProgress", args.timeout)["params"]
            if progress["state"] == "completed":
                break
            if progress["state"] == "canceled":
                raise PageError("the browser cancelled the download of the results")
        with open(os.path.join(downloads, done["suggestedFilename"]), encoding="utf-8") as f:
            downloaded = f.read()
        if downloaded != shown:
            raise PageError("the downloaded CSV differs from the one the page shows")
        posted = None
        if url.startswith("http"):
            posted = page.wait_for("document.body.dataset.posted", "the results to be posted")
            status = page.evaluate("document.getElementById('post-status').textContent")
            if posted != "saved":
                raise PageError("posting the results failed: " + status)
        page.check_errors()
    finally:
        browser.close()
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(downloaded)
    if args.given:
        with open(args.given, "w", encoding="utf-8") as f:
            json.dump({"listener": args.name, "given": given}, f, indent=1)
    shutil.rmtree(downloads, ignore_errors=True)

    for g in given:
        print("gave %g to %s (letter %s) on %s" % (g["score"], g["condition"], g["letter"], g["page"]))
    advanced = [after - before for before, after, _, _ in audio_report]
    state, rate = audio_report[-1][2], audio_report[-1][3]
    print("audio: AudioContext %s at %g Hz; its clock advanced %.3f..%.3f s in each 0.12 s of listening"
          % (state, rate, min(advanced), max(advanced)))
    print("pages ready (audio decoded) %.2f..%.2f s after they were shown" % (min(ready_s), max(ready_s)))
    print("downloaded %s (%d rows)%s; %.1f s" % (done["suggestedFilename"], len(given),
                                                  ", posted to the server" if posted else "",
                                                  time.monotonic() - started))
    print("wrote " + args.out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("target", help="the test folder (opened from the file system) or the served URL")
    parser.add_argument("--out", required=True, help="where to write the CSV the page produced")
    parser.add_argument("--name", default="Scripted Listener", help="the listener's name to type")
    parser.add_argument("--scores", default="", help="CONDITION=SCORE,... given on every page")
    parser.add_argument("--seed", type=int, default=1, help="draws the scores of conditions --scores leaves out")
    parser.add_argument("--given", help="write the scores given (JSON) here")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds to wait for any one step")
    parser.add_argument("--chromium", help="the browser (default: chromium on the PATH)")
    parser.add_argument("--browser-log", help="write the browser's own output here")
    parser.add_argument("--screenshot", help="save a PNG of the first page, rated, here")
    parser.add_argument("--no-autoplay-flag", action="store_true",
                        help="leave out --autoplay-policy=no-user-gesture-required (to see whether clicks suffice)")
    args = parser.parse_args()
    try:
        run(args)
    except PageError as error:
        print("mushra_listener: " + str(error), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
