"""The browser client in a real browser (Debian's chromium, headless): the page loads with the
printed token, shows frames, sends a key press that turns the view, and is screenshotted; the
same page without the token is refused. Usage: browser_test.py BUILD OUT_DIR"""
import os
import sys
import unittest

import cdp
import web_farm

BUILD = sys.argv.pop(1) if len(sys.argv) > 1 else "build"
OUT = sys.argv.pop(1) if len(sys.argv) > 1 else "."

# The canvas' pixels, kept in the page to compare against later.
SNAPSHOT = """(() => { const c = document.getElementById('frame');
  window.snapshot = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; return true; })()"""
# Mean absolute difference (0-255) between the canvas now and the snapshot, over the means of
# 16x16-pixel blocks: a turned view moves every block's picture, while a converging still view
# changes its blocks' means little even when workload scaling changes the render size or the
# samples per pixel (each pixel's noise then changes, its block's mean hardly).
CHANGE = """(() => { const c = document.getElementById('frame');
  const now = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  if (now.length !== window.snapshot.length) return 255;
  const bw = Math.ceil(c.width / 16), bh = Math.ceil(c.height / 16);
  const diff = new Float64Array(bw * bh * 3), count = new Float64Array(bw * bh);
  for (let y = 0; y < c.height; y++)
    for (let x = 0; x < c.width; x++) {
      const b = Math.floor(y / 16) * bw + Math.floor(x / 16), i = (y * c.width + x) * 4;
      for (let k = 0; k < 3; k++) diff[b * 3 + k] += now[i + k] - window.snapshot[i + k];
      count[b] += 1;
    }
  let sum = 0; for (let b = 0; b < bw * bh; b++)
    for (let k = 0; k < 3; k++) sum += Math.abs(diff[b * 3 + k]) / count[b];
  return sum / (bw * bh * 3); })()"""


class BrowserTest(unittest.TestCase):
    def test_page_shows_frames_and_a_key_turns_the_view(self):
        os.makedirs(OUT, exist_ok=True)
        # The free camera: builtin:default's own game switches a light on a timer, which
        # changed the whole picture within the "still" windows below now and then.
        with web_farm.Farm(BUILD, scene="builtin:default", tracers=2, size=(256, 144),
                           extra=("--game", "free-camera")) as farm:
            browser = cdp.Chromium()
            try:
                # Debian's chromium has WebCodecs with H.264: the page picks it; ?codec=jpeg
                # makes it take JPEG, as a browser without a decoder would.
                self.play(browser, farm, farm.url, codec=1, name="browser_client")
                self.play(browser, farm, farm.url + "&codec=jpeg", codec=0,
                          name="browser_client_jpeg")
                # The same page without the token (nor the cookie the page set): refused.
                browser.call("Network.clearBrowserCookies")
                browser.call("Page.navigate", url=farm.base)
                browser.wait_until("document.readyState === 'complete'")
                self.assertIn("forbidden", browser.evaluate("document.body.innerText"))
            finally:
                browser.close()

    def play(self, browser, farm, url, codec, name):
        browser.call("Page.navigate", url=url)
        browser.wait_until("window.pathfarm && window.pathfarm.frames >= 10")
        self.assertTrue(browser.evaluate("window.pathfarm.connected"))
        header = browser.evaluate("window.pathfarm.lastHeader")
        self.assertEqual((header["width"], header["height"], header["codec"]), (256, 144, codec))
        # A still camera converges: frames differ little from one to the next (block means:
        # CHANGE). The quieter of two windows. Measured with two busy loops beside the test:
        # still 0.6-0.9, turned 33-50; per pixel and with the default game's light switching,
        # a still window read up to 13-20 and a turned JPEG one 28.
        still = float("inf")
        for _ in range(2):
            browser.evaluate(SNAPSHOT)
            start = browser.evaluate("window.pathfarm.frames")
            browser.wait_until(f"window.pathfarm.frames >= {start + 4}")
            still = min(still, browser.evaluate(CHANGE))
        browser.screenshot(os.path.join(OUT, name + ".png"))
        browser.evaluate(SNAPSHOT)
        browser.key("ArrowLeft", "ArrowLeft", 37, hold_seconds=0.6)
        browser.wait_until("window.pathfarm.latenciesMs.length > 0")
        browser.wait_until("window.pathfarm.sentAt.size === 0")
        start = browser.evaluate("window.pathfarm.frames")
        browser.wait_until(f"window.pathfarm.frames >= {start + 2}")  # decoded and drawn
        turned = browser.evaluate(CHANGE)
        self.assertGreater(turned, 4 * still + 2, (name, still, turned))
        overlay = browser.evaluate("document.getElementById('overlay').textContent")
        self.assertRegex(overlay, r"frames/s +latency p50 \d+ ms +p99 \d+ ms")
        self.assertRegex(overlay, r"render \d+x\d+ +\d+ spp +frame \d+ +" +
                         ("H.264" if codec else "JPEG"))
        browser.screenshot(os.path.join(OUT, name + "_turned.png"))


if __name__ == "__main__":
    unittest.main()
