// The page of `raydiance preview`: follows the server's event stream (each finished pass, the
// scene's error) and sends the tone mapping chosen; the server tone-maps.
"use strict";

const $ = (id) => document.getElementById(id);

function showState(state) {
  $("status").textContent = "connected";
  $("operator").value = state.operator;
  $("exposure").value = state.exposure;
  $("exposure-value").textContent = state.exposure;
  $("error").hidden = !state.error;
  const picture = state.picture;
  if (picture) {
    const img = $("picture");
    img.src = "/image.png?v=" + state.version;
    img.hidden = false;
    $("spp").textContent = picture.spp;
    $("target").textContent = picture.target;
    $("seconds").textContent = picture.seconds.toFixed(2);
    $("render").textContent = picture.render;
  }
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
