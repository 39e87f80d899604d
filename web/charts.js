// The path job's dashboard charts (uPlot): frame time against the target, HLODs drawn per level
// (stacked), up/down toggles, resident memory against the cap, and loads per frame. Each chart
// takes one FrameRecord per frame (push) and redraws at most once per animation frame.

import uPlot from './vendor/uplot/uPlot.esm.js';

const PLOT_HEIGHT = 160;
// Tick steps for whole numbers (frames, node counts): never a tick at 0.5 of a frame.
const WHOLE_STEPS = [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000, 20000, 50000, 1e5, 2e5, 5e5, 1e6];
// Levels from coarse (hlod_0) to fine, on a sequential scale that stays readable when stacked.
const LEVEL_COLOURS = ['#3b4cc0', '#5a78d6', '#7b9ff2', '#9ebeff', '#c0d4f5', '#dddcdc', '#f2cbb7',
  '#f7ac8e', '#ee8468', '#d65244', '#b40426'];

// One chart in a container element; series: [{label, colour, dash, fill, bars, value(record)}];
// whole: the values are counts (ticks on whole numbers).
class Chart {
  constructor(container, { title, yLabel, series, stacked = false, whole = false, yMin = 0 }) {
    this.container = container;
    this.title = title;
    this.yLabel = yLabel;
    this.stacked = stacked;
    this.whole = whole;
    this.yMin = yMin;
    this.pending = false;
    this.plot = null;
    this.setSeries(series);
    new ResizeObserver(() => this.plot && this.plot.setSize(this.size())).observe(container);
  }

  size() {
    return { width: Math.max(200, this.container.clientWidth), height: PLOT_HEIGHT };
  }

  // (Re)builds the plot for a set of series, dropping the points.
  setSeries(series) {
    this.series = series;
    this.x = [];
    this.raw = series.map(() => []);
    if (this.plot) this.plot.destroy();
    const options = {
      ...this.size(),
      title: this.title,
      scales: {
        x: { time: false },
        y: { range: (u, min, max) => [Math.min(this.yMin, min), max > min ? max * 1.05 : min + 1] },
      },
      axes: [
        { label: 'frame', labelSize: 16, size: 32, incrs: WHOLE_STEPS },
        { label: this.yLabel, labelSize: 16, size: 52, incrs: this.whole ? WHOLE_STEPS : undefined },
      ],
      cursor: { drag: { x: false, y: false } },
      legend: { live: true },
      series: [
        // Without the cursor over the plot, the legend shows the newest frame's values.
        { label: 'frame', value: (u, v) => (v == null ? this.x[this.x.length - 1] ?? '–' : v) },
        ...series.map((s, i) => ({
          label: s.label,
          stroke: s.colour,
          width: s.bars ? 0 : 1.5,
          dash: s.dash,
          fill: s.fill || (s.bars ? s.colour : undefined),
          paths: s.bars ? uPlot.paths.bars({ size: [0.8, 12] }) : undefined,
          points: { show: false },
          // A stacked series is drawn at its running sum; the legend shows its own value.
          value: (u, v, si, di) => formatValue(this.raw[i][di == null ? this.raw[i].length - 1 : di]),
        })),
      ],
    };
    // Stacked: fill each series down to the one below it.
    if (this.stacked) options.bands = series.slice(1).map((_, i) => ({ series: [i + 2, i + 1] }));
    this.plot = new uPlot(options, [[]].concat(series.map(() => [])), this.container);
  }

  push(x, record) {
    this.x.push(x);
    this.series.forEach((s, i) => this.raw[i].push(s.value(record)));
    this.scheduleRedraw();
  }

  scheduleRedraw() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.plot.setData([this.x].concat(this.plotted()));
    });
  }

  plotted() {
    if (!this.stacked) return this.raw;
    const sum = this.x.map(() => 0);
    return this.raw.map((values) => values.map((v, j) => (sum[j] += v || 0)));
  }

  points() {
    return this.x.length;
  }
}

function formatValue(v) {
  if (v == null || !Number.isFinite(v)) return '–';
  return Number.isInteger(v) ? String(v) : v.toFixed(v >= 100 ? 0 : v >= 10 ? 1 : 2);
}

// The levels of the blocks' nodes, below the cell nodes above the blocks (a store built with
// cells: `hlodr build --cells`), which are counted apart.
function levelSeries(count) {
  const cells = { label: 'cells', colour: '#777777', fill: '#777777', value: (r) => r.cellNodes || 0 };
  return [cells, ...Array.from({ length: count }, (_, level) => {
    const colour = LEVEL_COLOURS[Math.round((level * (LEVEL_COLOURS.length - 1)) / Math.max(1, count - 1))];
    return { label: `L${level}`, colour, fill: colour, value: (r) => (r.nodesPerLevel || [])[level] || 0 };
  })];
}

// All charts of the dashboard; reset() before a new job, add(record) per frame event.
export class Dashboard {
  // containers: {frameTime, levels, toggles, memory, loads} elements.
  constructor(containers) {
    this.levelCount = 1;
    this.lastLoads = null;
    this.charts = {
      frameTime: new Chart(containers.frameTime, {
        title: 'Frame time', yLabel: 'ms',
        series: [
          { label: 'actual', colour: '#1f5fbf', value: (r) => r.gpuMs },
          { label: 'target', colour: '#c0392b', dash: [6, 4], value: (r) => r.targetMs },
          { label: 'estimate', colour: '#8a8f98', dash: [2, 3], value: (r) => r.estimatedMs },
        ],
      }),
      levels: new Chart(containers.levels, {
        title: 'HLODs drawn per level (stacked)', yLabel: 'nodes', stacked: true, whole: true, series: levelSeries(1),
      }),
      toggles: new Chart(containers.toggles, {
        title: 'Toggles and occluded nodes per frame', yLabel: 'nodes', whole: true,
        series: [
          { label: 'up (finer)', colour: '#2e8b57', value: (r) => r.upToggles },
          { label: 'down (coarser)', colour: '#d2691e', value: (r) => r.downToggles },
          { label: 'occluded', colour: '#7f8c8d', dash: [4, 3], value: (r) => r.occludedNodes || 0 },
        ],
      }),
      memory: new Chart(containers.memory, {
        title: 'Resident node memory', yLabel: 'MiB',
        series: [
          { label: 'resident', colour: '#6a3d9a', fill: 'rgba(106, 61, 154, 0.12)', value: (r) => r.residentBytes / 1048576 },
          // No cap (0): no line rather than a line at zero.
          { label: 'cap', colour: '#c0392b', dash: [6, 4], value: (r) => (r.capBytes > 0 ? r.capBytes / 1048576 : null) },
        ],
      }),
      loads: new Chart(containers.loads, {
        title: 'Node loads per frame', yLabel: 'nodes', whole: true,
        series: [
          {
            label: 'loads', colour: '#3a7ca5', bars: true,
            // loadsFinished is cumulative: a frame's loads are the difference to the one before.
            value: (r) => {
              const previous = this.lastLoads;
              this.lastLoads = r.loadsFinished;
              return previous == null ? 0 : Math.max(0, r.loadsFinished - previous);
            },
          },
        ],
      }),
    };
  }

  // Empties every chart; levelCount: the scene's HLOD levels (the stacked chart's series).
  reset(levelCount) {
    this.levelCount = Math.max(1, levelCount || 1);
    this.lastLoads = null;
    this.charts.levels.setSeries(levelSeries(this.levelCount));
    for (const [name, chart] of Object.entries(this.charts)) {
      if (name !== 'levels') chart.setSeries(chart.series);
    }
  }

  add(record) {
    const levels = (record.nodesPerLevel || []).length;
    // A deeper front than the scene said: widen the stacked chart, keeping its points.
    if (levels > this.levelCount) {
      const chart = this.charts.levels;
      const kept = { x: chart.x, raw: chart.raw };
      this.levelCount = levels;
      chart.setSeries(levelSeries(levels));
      chart.x = kept.x;
      chart.raw = chart.series.map((_, i) => kept.raw[i] || kept.x.map(() => 0));
    }
    for (const chart of Object.values(this.charts)) chart.push(record.index, record);
  }

  // Points per chart, for the browser test's read-only hook.
  points() {
    return Object.fromEntries(Object.entries(this.charts).map(([name, c]) => [name, c.points()]));
  }
}
