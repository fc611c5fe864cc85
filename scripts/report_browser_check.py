#!/usr/bin/env python3
"""Open limbfuse HTML reports in headless Chromium and check them.

Drives Chromium through the DevTools protocol over --remote-debugging-pipe
(file descriptors 3 and 4, NUL-separated JSON): Python's standard library
only, no websocket client, no selenium, no network.

For each report: no console error, no uncaught exception, no failed
request; every expected element id present; every plot drawn (its script-made
axis ticks and a non-empty line) with its title inside its box, no tick
label "-0" / "-0.0" / NaN, every legend entry on one line; the time window responds (zoom in changes
every time plot's viewBox); a plot whose y range leaves out a start transient
keeps it over the whole trial and shows the transient on a window over the start. Optionally saves a screenshot of the first report.

usage: report_browser_check.py CHROMIUM OUT.png REPORT.html:ID,ID,... [REPORT.html:...]
"""

import base64
import fcntl
import json
import os
import subprocess
import sys
import tempfile
import time

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--remote-debugging-pipe",
]

CHECK_JS = r"""
(function (ids) {
  var out = { ready: document.body.dataset.ready || null, missing: [], undrawn: [], clipped: [], ticks: [], wrapped: [], clip: [], plots: 0, zoom: null };
  ids.forEach(function (id) { if (!document.getElementById(id)) out.missing.push(id); });
  document.querySelectorAll('svg.plot').forEach(function (svg) {
    out.plots++;
    var ticks = svg.querySelectorAll('g.axes text').length;
    var lines = Array.prototype.filter.call(svg.querySelectorAll('svg.area path'),
      function (p) { return (p.getAttribute('d') || '').length > 2; }).length;
    if (ticks < 3 || lines < 1) out.undrawn.push(svg.id + ' ticks=' + ticks + ' lines=' + lines);
    // the title inside the plot's box (review 27: plot-fes-sd's ran past its right edge)
    var title = svg.querySelector('text.title'), box = svg.viewBox.baseVal;
    if (title) {
      var bb = title.getBBox();
      if (bb.x + bb.width > box.x + box.width) out.clipped.push(svg.id + ' title ends at ' + Math.round(bb.x + bb.width) + ' of ' + box.width);
    }
    // no "-0", "-0.0" tick (audit 2026-12-05: ticks summed from a negative
    // start gave -2.8e-17, printed "-0.0") and no NaN/Infinity tick
    svg.querySelectorAll('g.axes text.ticklabel').forEach(function (t) {
      if (/^-0(\.0*)?$|NaN|Infinity|undefined/.test(t.textContent)) out.ticks.push(svg.id + ' tick "' + t.textContent + '"');
    });
  });
  // every legend entry on one line (audit 2026-12-05: a long estimate
  // file name broke at its hyphens, half an entry on the next line)
  document.querySelectorAll('.legend .key').forEach(function (k) {
    var r = k.getBoundingClientRect(), h = parseFloat(getComputedStyle(k).fontSize) * 1.9;
    if (k.getClientRects().length > 1 || r.height > h) out.wrapped.push((k.closest('figure').querySelector('svg.plot') || {}).id + ': ' + k.textContent);
  });
  // a clipped start transient (y_range.rs): the whole trial keeps the
  // clipped range, a window on the start shows the transient whole
  out.clip = [];
  var clipPlots = document.querySelectorAll('svg.plot[data-clip-until]');
  function heights() {
    return Array.prototype.map.call(clipPlots, function (p) { return p.querySelector('svg.area').viewBox.baseVal.height; });
  }
  if (clipPlots.length) {
    var whole = heights(), full = Array.prototype.map.call(clipPlots, function (p) {
      return +p.querySelector('svg.area').getAttribute('data-full').split(' ')[3];
    });
    clipPlots.forEach(function (p, i) {
      var until = +p.dataset.clipUntil / +p.dataset.xScale;
      document.getElementById('win-start').value = '0';
      document.getElementById('win-end').value = String(Math.max(until * 1.5, 0.1));
      document.getElementById('win-apply').click();
      var start = heights()[i];
      if (whole[i] > 1.3 * full[i]) out.clip.push(p.id + ': whole trial ' + whole[i] + ' high, clipped range ' + full[i]);
      if (start <= whole[i]) out.clip.push(p.id + ': the start window (' + start + ') does not show the transient beyond ' + whole[i]);
    });
    document.getElementById('win-all').click();
  }
  var time = document.querySelectorAll('svg.plot.time svg.area');
  if (time.length) {
    var before = Array.prototype.map.call(time, function (a) { return a.getAttribute('viewBox'); });
    document.getElementById('win-in').click();
    var after = Array.prototype.map.call(time, function (a) { return a.getAttribute('viewBox'); });
    var changed = before.filter(function (b, i) { return b !== after[i]; }).length;
    document.getElementById('win-all').click();
    out.zoom = { plots: time.length, changed: changed, window: document.body.dataset.window };
    // typed windows: an end before the start is swapped, an empty field keeps the window's
    var w = document.body.dataset.window.split(':').map(Number), span = w[1] - w[0];
    var lo = (w[0] + 0.3 * span).toFixed(3), hi = (w[0] + 0.6 * span).toFixed(3);
    document.getElementById('win-start').value = hi;
    document.getElementById('win-end').value = lo;
    document.getElementById('win-apply').click();
    var swapped = document.body.dataset.window;
    document.getElementById('win-start').value = '';  // (a number field holds no text: empty)
    document.getElementById('win-apply').click();
    out.typed = { expected: lo + ':' + hi, swapped: swapped, after_text: document.body.dataset.window };
    document.getElementById('win-all').click();
  }
  return JSON.stringify(out);
})
"""


class Browser:
    def __init__(self, exe, profile):
        r_cmd, w_cmd = os.pipe()  # we write commands -> browser reads fd 3
        r_res, w_res = os.pipe()  # browser writes fd 4 -> we read results
        def to_3_and_4():
            # Through fds >= 10 first, so that neither dup2 clobbers the other's source.
            a = fcntl.fcntl(r_cmd, fcntl.F_DUPFD, 10)
            b = fcntl.fcntl(w_res, fcntl.F_DUPFD, 10)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.proc = subprocess.Popen(
            [exe, *FLAGS, f"--user-data-dir={profile}", "about:blank"],
            close_fds=False,
            preexec_fn=to_3_and_4,
            stdout=subprocess.DEVNULL,
            stderr=open(os.path.join(profile, "chromium.log"), "wb"),
        )
        self.log = os.path.join(profile, "chromium.log")
        os.close(r_cmd)
        os.close(w_res)
        self.w = os.fdopen(w_cmd, "wb")
        self.r = os.fdopen(r_res, "rb")
        self.next_id = 0
        self.buf = b""
        self.events = []

    def _read(self):
        while b"\0" not in self.buf:
            chunk = self.r.read1(1 << 16)
            if not chunk:
                with open(self.log, "rb") as f:
                    tail = f.read().decode(errors="replace")[-2000:]
                raise RuntimeError("chromium closed the DevTools pipe: " + tail)
            self.buf += chunk
        msg, self.buf = self.buf.split(b"\0", 1)
        return json.loads(msg)

    def send(self, method, params=None, session=None):
        self.next_id += 1
        msg = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        self.w.write(json.dumps(msg).encode() + b"\0")
        self.w.flush()
        while True:
            m = self._read()
            if m.get("id") == self.next_id:
                if "error" in m:
                    raise RuntimeError(f"{method}: {m['error']}")
                return m.get("result", {})
            self.events.append(m)

    def wait_event(self, name, session, timeout=30):
        end = time.time() + timeout
        while time.time() < end:
            for i, e in enumerate(self.events):
                if e.get("method") == name and e.get("sessionId") == session:
                    return self.events.pop(i)
            self.events.append(self._read())
        raise RuntimeError(f"timeout waiting for {name}")

    def close(self):
        try:
            self.send("Browser.close")
        except Exception:
            pass
        self.proc.wait(timeout=20)


def problems_in(events, session):
    out = []
    for e in events:
        if e.get("sessionId") != session:
            continue
        m, p = e.get("method"), e.get("params", {})
        if m == "Runtime.exceptionThrown":
            out.append("exception: " + json.dumps(p.get("exceptionDetails", {}))[:500])
        elif m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert", "warning"):
            out.append("console." + p["type"] + ": " + json.dumps(p.get("args"))[:500])
        elif m == "Log.entryAdded" and p.get("entry", {}).get("level") in ("error", "warning"):
            out.append("log: " + json.dumps(p["entry"])[:500])
        elif m == "Network.loadingFailed":
            out.append("request failed: " + json.dumps(p)[:300])
        elif m == "Network.requestWillBeSent":
            url = p.get("request", {}).get("url", "")
            if not url.startswith(("file:", "data:", "about:")):
                out.append("network request: " + url)
    return out


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    exe, png, specs = sys.argv[1], sys.argv[2], sys.argv[3:]
    failures = []
    with tempfile.TemporaryDirectory() as profile:
        b = Browser(exe, profile)
        try:
            for k, spec in enumerate(specs):
                path, _, ids = spec.partition(":")
                ids = [i for i in ids.split(",") if i]
                target = b.send("Target.createTarget", {"url": "about:blank"})["targetId"]
                s = b.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
                for domain in ("Page", "Runtime", "Log", "Network"):
                    b.send(domain + ".enable", session=s)
                b.send("Emulation.setDeviceMetricsOverride",
                       {"width": 1100, "height": 1500, "deviceScaleFactor": 1, "mobile": False}, session=s)
                b.send("Page.navigate", {"url": "file://" + os.path.abspath(path)}, session=s)
                b.wait_event("Page.loadEventFired", s)
                res = b.send("Runtime.evaluate", {"expression": CHECK_JS + "(" + json.dumps(ids) + ")",
                                                  "returnByValue": True}, session=s)
                if "exceptionDetails" in res:
                    failures.append(f"{path}: check script failed: {res['exceptionDetails']}")
                    continue
                r = json.loads(res["result"]["value"])
                time.sleep(0.2)
                b.send("Runtime.evaluate", {"expression": "1"}, session=s)  # drain late events
                bad = problems_in(b.events, s)
                if r["ready"] is None:
                    bad.append("the page script did not finish (body[data-ready] unset)")
                bad += ["missing #" + i for i in r["missing"]]
                bad += ["not drawn: " + u for u in r["undrawn"]]
                bad += ["clipped: " + u for u in r["clipped"]]
                bad += ["tick label: " + u for u in r["ticks"]]
                bad += ["legend entry on two lines: " + u for u in r["wrapped"]]
                bad += ["start transient: " + u for u in r["clip"]]
                z = r["zoom"]
                if z is not None and z["changed"] != z["plots"]:
                    bad.append(f"zoom changed {z['changed']} of {z['plots']} time plots")
                typed = r.get("typed")
                if typed is not None and not (
                    typed["swapped"] == typed["expected"] and typed["after_text"] == typed["expected"]
                ):
                    bad.append(f"typed window: {typed}")
                print(f"{path}: {r['plots']} plots, {len(ids)} ids checked, zoom {z}, "
                      f"{'OK' if not bad else 'FAILED'}")
                failures += [f"{path}: {x}" for x in bad]
                if k == 0 and png:
                    shot = b.send("Page.captureScreenshot", {"format": "png"}, session=s)
                    with open(png, "wb") as f:
                        f.write(base64.b64decode(shot["data"]))
                    print(f"screenshot: {png}")
                b.send("Target.closeTarget", {"targetId": target})
        finally:
            b.close()
    for f in failures:
        print("FAIL " + f, file=sys.stderr)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
