// A vehicle's position and track on a plain canvas: local metres around the first fix
// (equirectangular, plenty for a few km), equal axis scales, a light grid with its spacing.
class PositionPlot {
  constructor(canvas, maxPoints = 2000) {
    this.canvas = canvas;
    this.maxPoints = maxPoints;
    this.track = [];      // [x_m, y_m]
    this.origin = null;   // {lat, lon}
  }

  add(pos) {
    if (!pos || typeof pos.lat !== "number" || typeof pos.lon !== "number") return;
    if (!this.origin) this.origin = { lat: pos.lat, lon: pos.lon };
    const metresPerDegree = 111320;
    const x = (pos.lon - this.origin.lon) * metresPerDegree * Math.cos((this.origin.lat * Math.PI) / 180);
    const y = (pos.lat - this.origin.lat) * metresPerDegree;
    const last = this.track[this.track.length - 1];
    if (last && Math.abs(last[0] - x) < 0.05 && Math.abs(last[1] - y) < 0.05) return;
    this.track.push([x, y]);
    if (this.track.length > this.maxPoints) this.track.shift();
  }

  draw() {
    const { canvas } = this;
    const context = canvas.getContext("2d");
    const width = canvas.width, height = canvas.height;
    context.fillStyle = "#0f1720";
    context.fillRect(0, 0, width, height);
    if (this.track.length === 0) {
      context.fillStyle = "#6b7c8f";
      context.font = "13px system-ui, sans-serif";
      context.fillText("no position yet", 12, 22);
      return;
    }
    let minX = Infinity, maxX = -Infinity, minY = Infinity, maxY = -Infinity;
    for (const [x, y] of this.track) {
      minX = Math.min(minX, x); maxX = Math.max(maxX, x);
      minY = Math.min(minY, y); maxY = Math.max(maxY, y);
    }
    const span = Math.max(maxX - minX, maxY - minY, 20) * 1.2;
    const centreX = (minX + maxX) / 2, centreY = (minY + maxY) / 2;
    const scale = Math.min(width, height) / span;
    const toScreen = ([x, y]) => [width / 2 + (x - centreX) * scale, height / 2 - (y - centreY) * scale];

    const gridStep = Math.pow(10, Math.floor(Math.log10(span / 2)));
    context.strokeStyle = "#1f2d3a";
    context.lineWidth = 1;
    const startX = Math.floor((centreX - span) / gridStep) * gridStep;
    const startY = Math.floor((centreY - span) / gridStep) * gridStep;
    for (let gx = startX; gx < centreX + span; gx += gridStep) {
      const [sx] = toScreen([gx, 0]);
      context.beginPath(); context.moveTo(sx, 0); context.lineTo(sx, height); context.stroke();
    }
    for (let gy = startY; gy < centreY + span; gy += gridStep) {
      const [, sy] = toScreen([0, gy]);
      context.beginPath(); context.moveTo(0, sy); context.lineTo(width, sy); context.stroke();
    }
    context.fillStyle = "#6b7c8f";
    context.font = "11px system-ui, sans-serif";
    context.fillText(`grid ${gridStep} m`, 8, height - 8);

    context.strokeStyle = "#38bdf8";
    context.lineWidth = 2;
    context.beginPath();
    this.track.forEach((point, index) => {
      const [sx, sy] = toScreen(point);
      if (index === 0) context.moveTo(sx, sy); else context.lineTo(sx, sy);
    });
    context.stroke();
    const [hx, hy] = toScreen(this.track[this.track.length - 1]);
    context.fillStyle = "#fbbf24";
    context.beginPath(); context.arc(hx, hy, 5, 0, 2 * Math.PI); context.fill();
  }
}
window.PositionPlot = PositionPlot;
