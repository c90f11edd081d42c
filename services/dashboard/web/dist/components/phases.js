// A job's phases (of its current round) as labelled progress bars, in plan order.
import { h, setText } from "../dom.js";
import { formatNumber, phaseLabel } from "../format.js";
import { progressBar, updateProgressBar } from "./widgets.js";
export class PhaseList {
    constructor() {
        this.sig = "";
        this.element = h("ol", { class: "phases", "aria-label": "Phases of the current round" });
    }
    update(job) {
        const phases = job.phases ?? [];
        const sig = phases.map((p) => p.phase).join(",");
        if (sig !== this.sig) {
            this.sig = sig;
            this.element.replaceChildren(...(phases.length
                ? phases.map((p) => h("li", { class: "phase", "data-phase": p.phase ?? "" }, h("span", { class: "phase__name" }, phaseLabel(p.phase)), h("span", { class: "phase__count" }), progressBar(0, "", { "aria-label": phaseLabel(p.phase) })))
                : [h("li", { class: "empty" }, "No phases planned yet.")]));
        }
        phases.forEach((p, i) => {
            const li = this.element.children[i];
            if (!li)
                return;
            const done = p.tasksSucceeded ?? 0;
            const total = p.tasksTotal ?? 0;
            const count = `${formatNumber(done)} / ${formatNumber(total)}`;
            setText(li.querySelector(".phase__count"), count);
            updateProgressBar(li.querySelector(".bar"), total ? done / total : 0, `${total ? Math.round((100 * done) / total) : 0}%`);
        });
    }
}
