// The login form, shown over the page whenever the API answers 401: the coordinator's
// client token, posted to /api/login (which sets an HttpOnly cookie).

import { ApiError, login } from "./api.js";
import { h } from "./dom.js";

/** Shows the form; resolves once the server accepted a token. */
export function showLogin(): Promise<void> {
  return new Promise((resolve) => {
    const input = h("input", {
      id: "login-token",
      name: "token",
      type: "password",
      autocomplete: "current-password",
      spellcheck: "false",
      "data-testid": "login-token",
      "aria-describedby": "login-help",
    });
    const error = h("p", { class: "form-error", role: "alert", id: "login-error" });
    const submit = h("button", { type: "submit", class: "button button--primary", "data-testid": "login-submit" }, "Sign in");
    const form = h(
      "form",
      { class: "login card", "aria-labelledby": "login-title" },
      h("h1", { id: "login-title", class: "login__title" }, "Sign in to the render farm"),
      h(
        "p",
        { id: "login-help", class: "muted" },
        "Enter the coordinator's client token. It is kept in a secure cookie for this browser session.",
      ),
      h("label", { for: "login-token", class: "field__label" }, "Access token"),
      input,
      error,
      submit,
    );
    const overlay = h("div", { class: "overlay", role: "dialog", "aria-modal": "true", "aria-labelledby": "login-title" }, form);

    form.addEventListener("submit", async (ev) => {
      ev.preventDefault();
      submit.disabled = true;
      error.textContent = "";
      try {
        await login(input.value.trim());
        overlay.remove();
        resolve();
      } catch (err) {
        error.textContent =
          err instanceof ApiError && err.status === 401
            ? `The coordinator refused this token: ${err.message}`
            : `Could not sign in: ${err instanceof Error ? err.message : String(err)}`;
        submit.disabled = false;
        input.select();
      }
    });
    document.body.append(overlay);
    input.focus();
  });
}
