// The plots of the page, drawn with Chart.js (tree-shaken: only the pieces used are registered):
// the albedo curve, the polar lobe in the plane of incidence, and the largest weights.
import {
  BarController,
  BarElement,
  CategoryScale,
  Chart,
  Legend,
  LinearScale,
  LineController,
  LineElement,
  PointElement,
  ScatterController,
  Tooltip,
} from "chart.js";
import type { AlbedoReply, LobeReply, WeightsReply } from "./api";
import { niceStep } from "./map-geometry";

Chart.register(
  BarController, BarElement, CategoryScale, Legend, LinearScale, LineController, LineElement,
  PointElement, ScatterController, Tooltip,
);
Chart.defaults.color = "#9aa3b2";
Chart.defaults.borderColor = "rgba(255,255,255,0.08)";
Chart.defaults.font.size = 11;
Chart.defaults.animation = false;

const CHANNELS = [
  { label: "R", color: "#ff6b6b" },
  { label: "G", color: "#5fd38d" },
  { label: "B", color: "#5aa9ff" },
];

export class AlbedoChart {
  private chart: Chart<"line", { x: number; y: number }[]>;

  constructor(canvas: HTMLCanvasElement) {
    this.chart = new Chart(canvas, {
      type: "line",
      data: {
        datasets: CHANNELS.map((c) => ({
          label: c.label, data: [], borderColor: c.color, backgroundColor: c.color,
          pointRadius: 0, borderWidth: 1.5,
        })),
      },
      options: {
        responsive: true, maintainAspectRatio: false, parsing: false,
        scales: {
          x: { type: "linear", min: 0, max: 90, title: { display: true, text: "θo (degrees)" } },
          y: { type: "linear", min: 0, title: { display: true, text: "directional albedo" } },
        },
        plugins: { legend: { display: false } },
      },
    });
  }

  update(reply: AlbedoReply): void {
    this.chart.data.datasets.forEach((ds, c) => {
      ds.data = reply.theta_o.map((t, i) => ({ x: t, y: reply.rgb[i][c] }));
    });
    this.chart.update("none");
  }
}

/** Lobe in polar form: radius f (or log(1 + f / 0.01)), angle theta_o from the normal. */
export class LobeChart {
  private chart: Chart<"scatter", { x: number; y: number }[]>;
  logScale = true;
  private last: LobeReply | null = null;
  /** The radius scale's rings of the last frame: BRDF values (sr^-1) and their radii in plot units. */
  rings: { value: number; radius: number }[] = [];

  constructor(canvas: HTMLCanvasElement) {
    this.chart = new Chart(canvas, {
      type: "scatter",
      data: {
        datasets: [
          ...CHANNELS.map((c) => ({
            label: c.label, data: [] as { x: number; y: number }[], borderColor: c.color,
            backgroundColor: c.color, showLine: true, pointRadius: 0, borderWidth: 1.5,
          })),
          {
            label: "incidence", data: [], borderColor: "rgba(245,192,74,0.9)", backgroundColor: "transparent",
            showLine: true, pointRadius: 0, borderWidth: 1, borderDash: [4, 3],
          },
        ],
      },
      options: {
        responsive: true, maintainAspectRatio: false,
        scales: {
          x: { type: "linear", ticks: { display: false }, grid: { color: "rgba(255,255,255,0.05)" } },
          y: { type: "linear", min: 0, ticks: { display: false }, grid: { color: "rgba(255,255,255,0.05)" } },
        },
        plugins: { legend: { display: false }, tooltip: { enabled: false } },
      },
      plugins: [{
        // The radius scale: half rings at round BRDF values, labelled on the right.
        id: "rings",
        beforeDatasetsDraw: (chart) => {
          const { ctx, scales: { x, y } } = chart;
          ctx.save();
          ctx.font = "10px system-ui, sans-serif";
          ctx.textAlign = "left";
          ctx.textBaseline = "bottom";
          for (const ring of this.rings) {
            const rx = x.getPixelForValue(ring.radius) - x.getPixelForValue(0);
            const ry = y.getPixelForValue(0) - y.getPixelForValue(ring.radius);
            ctx.strokeStyle = "rgba(255,255,255,0.16)";
            ctx.beginPath();
            ctx.ellipse(x.getPixelForValue(0), y.getPixelForValue(0), rx, ry, 0, Math.PI, 2 * Math.PI);
            ctx.stroke();
            // Labelled on the ground line at the back (the side light comes from, rarely drawn on).
            ctx.fillStyle = "rgba(200,206,216,0.75)";
            ctx.fillText(fmtRing(ring.value), x.getPixelForValue(0) - rx + 2, y.getPixelForValue(0) - 1);
          }
          ctx.restore();
        },
      }],
    });
  }

  update(reply: LobeReply | null = this.last): void {
    if (!reply) return;
    this.last = reply;
    const radius = (f: number) => (this.logScale ? Math.log1p(Math.max(f, 0) / 0.01) : Math.max(f, 0));
    let rmax = 1e-9;
    CHANNELS.forEach((_, c) => {
      const pts = reply.theta_o.map((t, i) => {
        const r = radius(reply.rgb[i][c]);
        rmax = Math.max(rmax, r);
        const a = (t * Math.PI) / 180;
        return { x: r * Math.sin(a), y: r * Math.cos(a) };
      });
      this.chart.data.datasets[c].data = pts;
    });
    const ti = (reply.theta_i * Math.PI) / 180;
    this.chart.data.datasets[3].data = [
      { x: -rmax * Math.sin(ti), y: rmax * Math.cos(ti) },
      { x: 0, y: 0 },
    ];
    this.rings = this.logScale
      ? [0.01, 0.1, 1, 10, 100, 1000].map((v) => ({ value: v, radius: radius(v) })).filter((g) => g.radius <= rmax * 1.02)
      : (() => {
        const fmax = rmax, step = niceStep(fmax / 3);
        const out: { value: number; radius: number }[] = [];
        for (let v = step; v <= fmax * 1.02; v += step) out.push({ value: v, radius: v });
        return out;
      })();
    const scales = this.chart.options.scales!;
    scales.x!.min = -rmax * 1.05;
    scales.x!.max = rmax * 1.05;
    scales.y!.max = rmax * 1.05;
    this.chart.update("none");
  }
}

const fmtRing = (v: number) => (v >= 1 ? String(Number(v.toPrecision(3))) : String(Number(v.toPrecision(2))));

export class WeightsChart {
  private chart: Chart<"bar", number[], string>;

  constructor(canvas: HTMLCanvasElement) {
    this.chart = new Chart(canvas, {
      type: "bar",
      data: { labels: [], datasets: [{ label: "weight", data: [], backgroundColor: [], borderWidth: 0 }] },
      options: {
        indexAxis: "y", responsive: true, maintainAspectRatio: false,
        scales: {
          x: { type: "linear" },
          // Long names shortened (the bar's tooltip has the whole name).
          y: { type: "category", ticks: { autoSkip: false, callback(v) {
            const name = String(this.getLabelForValue(Number(v)));
            return name.length > 20 ? `${name.slice(0, 19)}…` : name;
          } } },
        },
        plugins: { legend: { display: false } },
      },
    });
  }

  update(reply: WeightsReply): void {
    this.chart.data.labels = reply.top.map((t) => t.name);
    const ds = this.chart.data.datasets[0];
    ds.data = reply.top.map((t) => t.weight);
    ds.backgroundColor = reply.top.map((t) => (t.weight >= 0 ? "#4aa3ff" : "#ff8a5c"));
    this.chart.update("none");
  }
}
