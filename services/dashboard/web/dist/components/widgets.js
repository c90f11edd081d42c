// Small shared widgets: state badges, progress bars and timestamps.
import { h, setAttr, setText } from "../dom.js";
import { formatFullTimestamp, parseTime } from "../format.js";
/** A coloured state badge; tone is the CSS modifier ("running", "failed", "idle"...). */
export function badge(label, tone, attrs) {
    return h("span", { class: `badge badge--${tone}`, ...attrs }, label);
}
export function updateBadge(el, label, tone) {
    setText(el, label);
    const cls = `badge badge--${tone}`;
    if (el.className !== cls)
        el.className = cls;
}
/** A table cell's state badge: created on the first render, updated in place after. */
export function badgeCell(td, label, tone, attrs) {
    const el = td.firstElementChild;
    if (el)
        updateBadge(el, label, tone);
    else
        td.append(badge(label, tone, attrs));
}
/** A <time> of the timestamp ts, shown as text says, with the full local time as its title. */
export function timeElement(ts, text, attrs) {
    const ms = parseTime(ts);
    return h("time", { datetime: ts ?? "", title: formatFullTimestamp(ms), ...attrs }, text(ms));
}
/**
 * A progress bar (role=progressbar, with data-percent for tests) and its label.
 * fraction in [0, 1].
 */
export function progressBar(fraction, label, attrs) {
    const fill = h("div", { class: "bar__fill" });
    const el = h("div", { class: "bar", role: "progressbar", "aria-valuemin": "0", "aria-valuemax": "100", ...attrs }, h("div", { class: "bar__track" }, fill), h("span", { class: "bar__label" }));
    updateProgressBar(el, fraction, label);
    return el;
}
export function updateProgressBar(el, fraction, label) {
    const pct = Math.round(Math.min(1, Math.max(0, fraction)) * 1000) / 10;
    setAttr(el, "data-percent", String(pct));
    setAttr(el, "aria-valuenow", String(pct));
    setAttr(el, "aria-valuetext", label);
    const fill = el.querySelector(".bar__fill");
    if (fill) {
        const w = `${pct}%`;
        if (fill.style.width !== w)
            fill.style.width = w;
        fill.classList.toggle("bar__fill--done", pct >= 100);
    }
    const text = el.querySelector(".bar__label");
    if (text)
        setText(text, label);
}
