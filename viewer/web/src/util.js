// Small helpers shared by the page's modules: DOM building, the error banner, units, numbers.

/** Creates an element: el('td', {class: 'x', onclick: f}, 'text', child...). */
export function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (value === undefined || value === null || value === false) continue;
    if (key.startsWith('on') && typeof value === 'function') node.addEventListener(key.slice(2), value);
    else if (key === 'class') node.className = value;
    else if (key === 'dataset') Object.assign(node.dataset, value);
    else if (key in node && typeof value !== 'string') node[key] = value;
    else node.setAttribute(key, value === true ? '' : String(value));
  }
  for (const child of children.flat()) {
    if (child === undefined || child === null || child === false) continue;
    node.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return node;
}

export const $ = (id) => document.getElementById(id);

/** Appends the children to `parent`, skipping null, undefined and false (which DOM append would write as text). */
export function put(parent, ...children) {
  parent.append(...children.flat().filter((c) => c !== undefined && c !== null && c !== false));
}

const errorListeners = [];
/** Registers who else hears of errors (the state object's `errors`). */
export function onError(listener) { errorListeners.push(listener); }

/** Shows a message in the banner and records it; never throws, never logs to the console. */
export function showError(message) {
  const text = String(message instanceof Error ? message.message : message);
  const banner = $('banner');
  if (banner) {
    $('banner-text').textContent = text;
    banner.hidden = false;
  }
  for (const listener of errorListeners) listener(text);
}

export function hideError() {
  const banner = $('banner');
  if (banner) banner.hidden = true;
}

/** The unit of a channel, from the last part of its path (docs/recording.md: repository units). */
export function unitOf(path) {
  const leaf = path.split('/').pop();
  const base = leaf.replace(/\.[xyzw]$/, '');
  if (/Torque/i.test(base)) return 'N·m';
  if (/Angle$|Angle\b|^(Min|Max)Angle/.test(base)) return 'deg';
  if (/AngularVelocity|Speed$/i.test(base)) return 'deg/s';
  if (/^(Position|Anchor|Offset|Length|Radius|Width|Height|Depth)$/i.test(base)) return 'm';
  if (/Velocity/i.test(base)) return 'm/s';
  if (/Time$|TimeStep|Delay/.test(base)) return 's';
  if (/Mass$/.test(base)) return 'kg';
  if (/^Force/.test(base)) return 'N';
  return '';
}

/** Formats a number for tables and labels. */
export function fmt(value, digits = 4) {
  if (value === null || value === undefined || Number.isNaN(value)) return '—';
  if (typeof value !== 'number') return String(value);
  if (Number.isInteger(value)) return String(value);
  const a = Math.abs(value);
  if (a !== 0 && (a < 1e-3 || a >= 1e6)) return value.toExponential(3);
  return value.toFixed(digits);
}

/** Index of the last element <= x in a sorted array (0 if x is before the first). */
export function floorIndex(sorted, x) {
  let lo = 0, hi = sorted.length - 1;
  if (hi < 0 || x <= sorted[0]) return 0;
  if (x >= sorted[hi]) return hi;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (sorted[mid] <= x) lo = mid; else hi = mid - 1;
  }
  return lo;
}

/** Builds a predicate from a search text: /regex/flags, or else a case-insensitive substring. */
export function matcher(text) {
  const t = text.trim();
  const m = /^\/(.+)\/([a-z]*)$/.exec(t);
  if (m) {
    try {
      const re = new RegExp(m[1], m[2]);
      return (s) => re.test(s);
    } catch {
      return null;
    }
  }
  const needle = t.toLowerCase();
  return (s) => s.toLowerCase().includes(needle);
}
