// Dynamic resolution while the picture moves. Software GL (headless chromium, SwiftShader) pays for every pixel
// on the CPU: at full resolution a 680 × 770 view draws 27–40 frames a second, at half resolution the display's
// 60. The governor keeps the frame rate at the display's by lowering the drawing resolution while a recording
// plays or a live run runs, and gives full resolution back as soon as the picture stands still.

const WINDOW_MS = 500;      // frame rate measured over this long
const MIN_SCALE = 0.35;     // below this the robot is a smudge; frame rate is then what it is
const DOWN = 0.8;           // step down when frames come slower than the display's
const UP = 1.1;             // step up, carefully, when they keep up
const HEADROOM = 0.85;      // stay this far below a scale that fell behind
const PROBE_AFTER_MS = 4000;  // a scale that failed is tried again after this long at full rate (load moves)

export class ResolutionGovernor {
  constructor() {
    this.times = [];          // timestamps of animation frames within the last WINDOW_MS, ms
    this.displayRate = 60;    // the highest frame rate seen: what the display (or headless begin-frame) allows, 1/s
    this.movingScale = 1;     // the scale that kept up last time the picture moved (kept between plays)
    this.ceiling = 1;         // the lowest scale that fell behind; the governor stays below it until it probes
    this.movingSince = 0;     // when the current movement started, ms (0: standing still)
    this.lastDecision = 0;    // when the scale last changed or was confirmed, ms
    this.fullSince = 0;       // since when the frame rate has kept up, ms
  }

  /** Called once per animation frame; returns the resolution scale (0.35–1) to draw this frame at. */
  update(now, moving) {
    this.times.push(now);
    while (this.times.length && this.times[0] < now - WINDOW_MS) this.times.shift();
    const rate = (this.times.length * 1000) / WINDOW_MS;
    if (!moving) {
      this.movingSince = 0;
      return 1;
    }
    if (!this.movingSince) {
      this.movingSince = now;
      this.lastDecision = now;
      this.times = [now];
      return this.movingScale;
    }
    if (now - this.lastDecision < WINDOW_MS) return this.movingScale;
    this.lastDecision = now;
    this.displayRate = Math.max(this.displayRate, Math.min(rate, 240));
    const keepsUp = rate >= 0.95 * this.displayRate;
    if (!keepsUp) {
      this.fullSince = 0;
      this.ceiling = this.movingScale;
      this.movingScale = Math.max(MIN_SCALE, this.movingScale * DOWN);
    } else {
      if (!this.fullSince) this.fullSince = now;
      if (now - this.fullSince > PROBE_AFTER_MS) {
        this.ceiling = Math.min(1, this.ceiling * UP * UP);
        this.fullSince = now;
      }
      // Headroom below the scale that fell behind: probing right up to it would drop a frame every second.
      const next = Math.min(1, this.movingScale * UP);
      if (next <= HEADROOM * this.ceiling || this.ceiling >= 1 && next <= 1) this.movingScale = next;
    }
    return this.movingScale;
  }
}
