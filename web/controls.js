// controls.js: the page's controls, generated from the parameter table (`retroprism params
// --json`, written into site.json by `retroprism view`): a slider per float and per colour
// channel, a menu per enum, a checkbox per boolean. Vectors (normal, tangent) come from the
// geometry and get no control.

// A value of the table's JSON form (params_to_json) or of MaterialX's text form as the
// renderer's uniform value: float -> number, color3 -> [r, g, b], string -> enum index,
// boolean -> 0 or 1.
export function uniformValue(param, value) {
  switch (param.type) {
    case 'float':
      return Number(value);
    case 'color3':
      return typeof value === 'string' ? value.split(',').map(Number) : value.map(Number);
    case 'string': {
      const i = param.values.indexOf(String(value));
      return i >= 0 ? i : Number(value);
    }
    case 'boolean':
      return value === true || value === 'true' || value === 1 || value === '1' ? 1 : 0;
    default:
      return value;
  }
}

// The MaterialX type of an input of the table: an enum (JSON type "string", its names in
// `values`) is an integer enum in the nodedef, its value the index of the name.
export function mtlxType(param) {
  return param.type === 'string' ? 'integer' : param.type;
}

// A uniform value back in MaterialX's text form (for the exported document).
export function valueString(param, u) {
  const num = (x) => String(Number(x.toPrecision(6)));
  switch (param.type) {
    case 'float':
      return num(u);
    case 'color3':
      return u.map(num).join(', ');
    case 'string':
      return String(u);
    case 'boolean':
      return u ? 'true' : 'false';
    default:
      return String(u);
  }
}

function slider(min, max, value, id, onInput) {
  const s = document.createElement('input');
  s.type = 'range';
  s.min = String(min);
  s.max = String(max);
  s.step = String((max - min) / 1000);
  s.value = String(value);
  s.id = id;
  const box = document.createElement('input');
  box.type = 'number';
  box.min = s.min;
  box.max = s.max;
  box.step = 'any';
  box.value = String(value);
  box.className = 'num';
  const set = (v, from) => {
    const x = Math.min(max, Math.max(min, Number(v)));
    if (!Number.isFinite(x)) return;
    if (from !== s) s.value = String(x);
    if (from !== box) box.value = String(Number(x.toPrecision(6)));
    onInput(x);
  };
  s.addEventListener('input', () => set(s.value, s));
  box.addEventListener('change', () => set(box.value, box));
  return [s, box];
}

function row(label, title, ...elements) {
  const r = document.createElement('div');
  r.className = 'control';
  const l = document.createElement('label');
  l.textContent = label;
  l.title = title;
  if (elements[0] && elements[0].id) l.htmlFor = elements[0].id;
  r.append(l, ...elements);
  return r;
}

// Fills `container` with a control per input of `params` (the table) whose uniform exists;
// `values` (name -> uniform value) are the starting values and are updated in place;
// onChange(name) after each change.
export function buildControls(container, params, values, onChange) {
  container.replaceChildren();
  for (const p of params) {
    if (!(p.name in values)) continue;
    const id = `input-${p.name}`;
    const changed = (v) => {
      values[p.name] = v;
      onChange(p.name);
    };
    if (p.type === 'float') {
      container.append(row(p.name, p.doc, ...slider(p.min, p.max, values[p.name], id, changed)));
    } else if (p.type === 'color3') {
      const rgb = values[p.name].slice();
      ['r', 'g', 'b'].forEach((c, k) => {
        const set = (v) => {
          rgb[k] = v;
          changed(rgb.slice());
        };
        container.append(row(`${p.name}.${c}`, p.doc, ...slider(p.min, p.max, rgb[k], `${id}-${c}`, set)));
      });
    } else if (p.type === 'string') {
      const s = document.createElement('select');
      s.id = id;
      p.values.forEach((v, i) => s.add(new Option(v, String(i), false, i === values[p.name])));
      s.addEventListener('change', () => changed(Number(s.value)));
      container.append(row(p.name, p.doc, s));
    } else if (p.type === 'boolean') {
      const c = document.createElement('input');
      c.type = 'checkbox';
      c.id = id;
      c.checked = values[p.name] !== 0;
      c.addEventListener('change', () => changed(c.checked ? 1 : 0));
      container.append(row(p.name, p.doc, c));
    }
  }
}

// A slider row for a scene quantity (angles, exposure).
export function sceneControl(container, label, title, min, max, value, id, onInput) {
  container.append(row(label, title, ...slider(min, max, value, id, onInput)));
}
