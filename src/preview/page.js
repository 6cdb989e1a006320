// The page of `raydiance preview`: follows the server's event stream (each finished pass, its
// denoised view when raydiance denoises, the scene's error) and sends the tone mapping chosen;
// the server tone-maps. The page of a preview that denoises has the choice of view, raw (the
// pass as rendered) at first.
"use strict";

const $ = (id) => document.getElementById(id);

// Images asked for, in order: the one shown is the newest that arrived.
let asked = 0;
let shown = 0;
// What was last asked for: the PNG's number and the view (`render` or `denoised`).
let askedKey = "";
// The last state, shown again when the view changes.
let last = null;

function showPicture(picture, denoised) {
  $("spp").textContent = picture.spp;
  $("glance").hidden = !picture.glance;
  $("view-denoised").hidden = !denoised;
  $("target").textContent = picture.target;
  $("seconds").textContent = picture.seconds.toFixed(2);
  $("render").textContent = picture.render;
}

// Whether the denoised view is chosen (never in the page of a preview that does not denoise).
function denoisedChosen() {
  const choice = document.querySelector('input[name="view"]:checked');
  return Boolean(choice && choice.value === "denoised");
}

function showState(state) {
  last = state;
  $("status").textContent = "connected";
  $("operator").value = state.operator;
  $("exposure").value = state.exposure;
  $("exposure-value").textContent = state.exposure;
  $("error").hidden = !state.error;
  const picture = state.picture;
  const saveDenoised = $("save-denoised");
  if (saveDenoised) {
    saveDenoised.hidden = !(picture && picture.denoised);
  }
  // The denoised view when it is chosen and this pass has one; the pass as rendered until then.
  const denoised = Boolean(picture && picture.denoised && denoisedChosen());
  const key = picture ? picture.png + (denoised ? "denoised" : "render") : "";
  if (!picture || key === askedKey) {
    return;
  }
  // The new image is loaded aside and put in place whole, with its numbers: the page never
  // shows half an image, nor numbers newer than the image.
  askedKey = key;
  const number = ++asked;
  const next = new Image();
  next.onload = () => {
    if (number > shown) {
      shown = number;
      next.id = "picture";
      next.alt = denoised ? "the render, denoised" : "the render";
      // A glance is smaller than the render: shown at the render's size.
      next.width = picture.width;
      next.height = picture.height;
      $("picture").replaceWith(next);
      showPicture(picture, denoised);
    }
  };
  // A newer pass came first (its denoised view is not there yet): the next state asks again.
  next.onerror = () => {
    if (askedKey === key) {
      askedKey = "";
    }
  };
  next.src = (denoised ? "/denoised.png?n=" : "/image.png?n=") + picture.png;
}

const events = new EventSource("/events");
events.addEventListener("state", (e) => showState(JSON.parse(e.data)));
events.addEventListener("scene-error", (e) => {
  $("error-text").textContent = e.data;
});
events.onerror = () => {
  $("status").textContent = "disconnected: is raydiance preview still running?";
};

function sendToneMap() {
  $("exposure-value").textContent = $("exposure").value;
  const query = new URLSearchParams({ op: $("operator").value, exposure: $("exposure").value });
  fetch("/tonemap?" + query, { method: "POST" });
}
$("exposure").addEventListener("input", sendToneMap);
$("operator").addEventListener("change", sendToneMap);
for (const choice of document.querySelectorAll('input[name="view"]')) {
  choice.addEventListener("change", () => last && showState(last));
}
