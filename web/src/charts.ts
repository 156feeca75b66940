// Line charts of (x, y) series with Chart.js; zoom and pan by chartjs-plugin-zoom. Each
// canvas keeps its chart until the next is drawn on it or the view is left.
import {
  Chart, LineController, LineElement, PointElement, LinearScale, Legend, Title, Tooltip,
} from 'chart.js';
import zoomPlugin from 'chartjs-plugin-zoom';

Chart.register(LineController, LineElement, PointElement, LinearScale, Legend, Title, Tooltip, zoomPlugin);

export type Point = { x: number; y: number };

export type Series = {
  label: string;
  data: Point[];
  dash?: number[];
  color?: string;
  points?: boolean;
  /** Joined by a line (default); false: markers alone (a cloud of candidates). */
  line?: boolean;
};

export type Axes = { x: string; y: string; title?: string; equal?: boolean; zoom?: boolean };

// Colour-blind-safe (Okabe-Ito), each series also with its own dash: no line hides another.
const COLOURS = ['#0072B2', '#E69F00', '#009E73', '#CC79A7', '#56B4E9', '#D55E00', '#000000'];

const live: Chart[] = [];

/** The chart drawn on each canvas. */
const drawn = new WeakMap<HTMLCanvasElement, Chart>();

/** The chart drawn on `canvas`, or undefined (to reset its zoom). */
export function chartOf(canvas: HTMLCanvasElement): Chart | undefined {
  return drawn.get(canvas);
}

export function destroyCharts() {
  while (live.length) live.pop()!.destroy();
}

export function lineChart(canvas: HTMLCanvasElement, series: Series[], axes: Axes): Chart {
  drawn.get(canvas)?.destroy();
  let bounds = {};
  if (axes.equal) {
    const all = series.flatMap((s) => s.data);
    const r = Math.max(...all.map((p) => Math.max(Math.abs(p.x), Math.abs(p.y)))) * 1.05;
    bounds = { min: -r, max: r };
  }
  const chart = new Chart(canvas, {
    type: 'line',
    data: {
      datasets: series.map((s, i) => ({
        label: s.label,
        data: s.data,
        borderColor: s.color ?? COLOURS[i % COLOURS.length],
        backgroundColor: s.color ?? COLOURS[i % COLOURS.length],
        borderDash: s.dash ?? [],
        borderWidth: 1.5,
        pointRadius: s.line === false ? 5 : s.points ? 3 : 0,
        showLine: s.line ?? true,
        tension: 0,
      })),
    },
    options: {
      animation: false,
      responsive: true,
      maintainAspectRatio: true,
      aspectRatio: axes.equal ? 1 : 2,
      interaction: { mode: 'nearest', intersect: false },
      scales: {
        x: { type: 'linear', title: { display: true, text: axes.x }, ...bounds },
        y: { type: 'linear', title: { display: true, text: axes.y }, ...bounds },
      },
      plugins: {
        title: { display: !!axes.title, text: axes.title ?? '' },
        legend: { position: 'bottom' },
        zoom: axes.zoom ? {
          zoom: { wheel: { enabled: true }, pinch: { enabled: true }, mode: 'xy' },
          pan: { enabled: true, mode: 'xy' },
        } : undefined,
      },
    },
  });
  drawn.set(canvas, chart);
  // The end-to-end test reads what was drawn from the canvas's `chart`.
  (canvas as HTMLCanvasElement & { chart?: Chart }).chart = chart;
  live.push(chart);
  return chart;
}
