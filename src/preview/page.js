// The page of `raydiance preview`: follows the server's event stream (each finished pass, the
// scene's error) and sends the tone mapping chosen; the server tone-maps.
"use strict";

const $ = (id) => document.getElementById(id);

// The number of the PNG shown, and of the newest asked for.
let shownPng = 0;
let askedPng = 0;

function showPicture(picture) {
  $("spp").textContent = picture.spp;
  $("glance").hidden = !picture.glance;
  $("target").textContent = picture.target;
  $("seconds").textContent = picture.seconds.toFixed(2);
  $("render").textContent = picture.render;
}

function showState(state) {
  $("status").textContent = "connected";
  $("operator").value = state.operator;
  $("exposure").value = state.exposure;
  $("exposure-value").textContent = state.exposure;
  $("error").hidden = !state.error;
  const picture = state.picture;
  if (!picture || picture.png === askedPng) {
    return;
  }
  // The new image is loaded aside and put in place whole, with its numbers: the page never
  // shows half an image, nor numbers newer than the image.
  askedPng = picture.png;
  const next = new Image();
  next.onload = () => {
    if (picture.png > shownPng) {
      shownPng = picture.png;
      next.id = "picture";
      next.alt = "the render";
      // A glance is smaller than the render: shown at the render's size.
      next.width = picture.width;
      next.height = picture.height;
      $("picture").replaceWith(next);
      showPicture(picture);
    }
  };
  next.src = "/image.png?n=" + picture.png;
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
