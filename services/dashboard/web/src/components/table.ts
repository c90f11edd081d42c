// A keyed data table: rows are kept by key and a cell is rebuilt only when what it shows
// changed, so a live table of hundreds of rows costs one DOM update per event and no
// per-row listeners (row clicks are delegated to the table).

import { h } from "../dom.js";

export interface Column<T> {
  header: string;
  /** Applied to the header and every cell ("num" right-aligns). */
  className?: string;
  /** Plain-text cells: the text is both the content and what decides re-rendering. */
  text?: (row: T, now: number) => string;
  /** Rich cells: sig says what the cell shows; render fills it when sig changed. */
  sig?: (row: T, now: number) => string;
  render?: (row: T, td: HTMLTableCellElement, now: number) => void;
}

export interface TableOptions<T> {
  caption: string;
  /** Hide the caption visually (it stays for screen readers). */
  captionHidden?: boolean;
  columns: Column<T>[];
  key: (row: T) => string;
  /** Attributes of a row (data-testid, data-*); re-applied on each update. */
  rowAttrs?: (row: T) => Record<string, string>;
  /** Where a click on the row (outside links and buttons) goes. */
  rowHref?: (row: T) => string;
  empty: string;
  className?: string;
}

interface RowState {
  tr: HTMLTableRowElement;
  sigs: string[];
  attrs: Record<string, string>;
}

export class DataTable<T> {
  readonly element: HTMLTableElement;
  private readonly tbody: HTMLTableSectionElement;
  private readonly rows = new Map<string, RowState>();
  private readonly emptyRow: HTMLTableRowElement;

  constructor(private readonly opts: TableOptions<T>) {
    const cols = opts.columns;
    this.tbody = h("tbody");
    this.emptyRow = h("tr", { class: "table__empty" }, h("td", { colspan: cols.length }, opts.empty));
    this.element = h(
      "table",
      { class: `table ${opts.className ?? ""}`.trim() },
      h("caption", { class: opts.captionHidden ? "visually-hidden" : "table__caption" }, opts.caption),
      h("thead", null, h("tr", null, ...cols.map((c) => h("th", { scope: "col", class: c.className }, c.header)))),
      this.tbody,
    );
    this.tbody.append(this.emptyRow);
    if (opts.rowHref) {
      this.tbody.addEventListener("click", (ev) => {
        const target = ev.target as Element;
        if (target.closest("a, button, input, select, label")) return;
        const tr = target.closest<HTMLTableRowElement>("tr[data-href]");
        const href = tr?.dataset["href"];
        if (href && !window.getSelection()?.toString()) location.hash = href;
      });
    }
  }

  /** Sets the text shown when there are no rows ("Loading…" before the first data). */
  setEmptyText(text: string): void {
    const td = this.emptyRow.cells[0];
    if (td && td.textContent !== text) td.textContent = text;
  }

  /** Shows rows, in this order. */
  update(rows: readonly T[], now: number): void {
    const { columns, key, rowAttrs, rowHref } = this.opts;
    const order: HTMLTableRowElement[] = [];
    const seen = new Set<string>();
    for (const row of rows) {
      const k = key(row);
      seen.add(k);
      let state = this.rows.get(k);
      if (!state) {
        const tr = h("tr", null, ...columns.map((c) => h("td", { class: c.className })));
        state = { tr, sigs: columns.map(() => "\u0000"), attrs: {} };
        this.rows.set(k, state);
      }
      const attrs = rowAttrs ? rowAttrs(row) : {};
      if (rowHref) attrs["data-href"] = rowHref(row);
      for (const [name, value] of Object.entries(attrs)) {
        if (state.attrs[name] !== value) state.tr.setAttribute(name, value);
      }
      state.attrs = attrs;
      const cells = state.tr.cells;
      columns.forEach((c, i) => {
        const td = cells[i]!;
        if (c.text) {
          const text = c.text(row, now);
          if (state!.sigs[i] !== text) {
            state!.sigs[i] = text;
            td.textContent = text;
          }
        } else if (c.sig && c.render) {
          const sig = c.sig(row, now);
          if (state!.sigs[i] !== sig) {
            state!.sigs[i] = sig;
            c.render(row, td, now);
          }
        }
      });
      order.push(state.tr);
    }
    for (const k of [...this.rows.keys()]) if (!seen.has(k)) this.rows.delete(k);

    const want: HTMLTableRowElement[] = order.length ? order : [this.emptyRow];
    const have = this.tbody.children;
    let same = have.length === want.length;
    for (let i = 0; same && i < want.length; i++) same = have[i] === want[i];
    if (!same) this.tbody.replaceChildren(...want);
  }
}
