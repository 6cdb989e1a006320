//! What the page shows, shared by the renderer (which publishes passes and errors), the server
//! (which streams it) and the page's controls (the tone mapping): the last good picture (and its
//! denoised view, when raydiance denoises), the scene's error if its last load failed, and a
//! version that grows with every change.

use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::Duration;

use crate::image::{Image, RenderInfo};
use crate::tonemap::{self, ToneMap};

/// A finished pass: its linear image and what the render was, tone-mapped for the page.
pub struct Picture {
    pub image: Image,
    pub info: RenderInfo,
    /// The samples per pixel the render aims at.
    pub target: u32,
    /// The render's image size (a glance's image is smaller: the page scales it up).
    pub size: (u32, u32),
    /// Whether this is the glance, the first image, of one sample per pixel at a reduced size.
    pub glance: bool,
    /// The render it belongs to (1 for the first load, one more for each reload).
    pub render: u64,
    png: Vec<u8>,
    /// Which PNG this is (one more at each pass, at its denoised view and at each change of
    /// tone mapping): the page loads the image again only when it changes.
    png_number: u64,
    /// The pass denoised, once the denoiser is done with it: a view beside the unbiased image,
    /// never in its place.
    pub denoised: Option<Denoised>,
}

/// A pass denoised: the image, with its `raydiance:denoised` parameter among the render's,
/// and as the page shows it.
pub struct Denoised {
    pub image: Image,
    pub info: RenderInfo,
    png: Vec<u8>,
}

#[derive(Default)]
struct State {
    version: u64,
    /// Whether passes are denoised (raydiance built with `denoise`, and the device made).
    denoising: bool,
    /// The render under way or last done.
    render: u64,
    picture: Option<Picture>,
    /// The last load's error as the terminal prints it; the picture stays beside it.
    error: Option<String>,
    tone_map: ToneMap,
}

#[derive(Default)]
pub struct Shown {
    state: Mutex<State>,
    changed: Condvar,
}

impl Shown {
    /// What the page shows of a preview that denoises its passes or not.
    pub fn new(denoising: bool) -> Shown {
        let shown = Shown::default();
        shown.state().denoising = denoising;
        shown
    }

    fn state(&self) -> MutexGuard<'_, State> {
        // A panic elsewhere while holding the lock leaves a state that is still whole.
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    fn publish(&self, change: impl FnOnce(&mut State)) {
        let mut state = self.state();
        change(&mut state);
        state.version += 1;
        self.changed.notify_all();
    }

    /// A new load of the scene starts; its number.
    pub fn render_starts(&self) -> u64 {
        let mut render = 0;
        self.publish(|state| {
            state.render += 1;
            render = state.render;
        });
        render
    }

    /// A pass of render `render` is done: it becomes the picture, and the error goes.
    pub fn pass(
        &self,
        render: u64,
        image: Image,
        info: RenderInfo,
        target: u32,
        size: (u32, u32),
        glance: bool,
    ) {
        let tone_map = self.state().tone_map.clone();
        let png = encode(&image, &tone_map);
        self.publish(|state| {
            let png_number = state.picture.as_ref().map_or(1, |p| p.png_number + 1);
            let denoised = None;
            let picture =
                Picture { image, info, target, size, glance, render, png, png_number, denoised };
            state.picture = Some(picture);
            state.error = None;
        });
    }

    /// The last pass, denoised: shown beside it (the render thread publishes both, so it is
    /// still the picture).
    pub fn denoised(&self, image: Image, info: RenderInfo) {
        let tone_map = self.state().tone_map.clone();
        let png = encode(&image, &tone_map);
        self.publish(|state| {
            if let Some(picture) = &mut state.picture {
                picture.denoised = Some(Denoised { image, info, png });
                picture.png_number += 1;
            }
        });
    }

    /// The scene did not load: the error is shown beside the last good picture.
    pub fn failed(&self, error: String) {
        self.publish(|state| state.error = Some(error));
    }

    /// The page chose another tone mapping: the picture is tone-mapped again.
    pub fn set_tone_map(&self, tone_map: ToneMap) {
        self.publish(|state| {
            if let Some(picture) = &mut state.picture {
                picture.png = encode(&picture.image, &tone_map);
                if let Some(denoised) = &mut picture.denoised {
                    denoised.png = encode(&denoised.image, &tone_map);
                }
                picture.png_number += 1;
            }
            state.tone_map = tone_map;
        });
    }

    /// The picture as PNG, as the page shows it.
    pub fn png(&self) -> Option<Vec<u8>> {
        self.state().picture.as_ref().map(|picture| picture.png.clone())
    }

    /// The picture's denoised view as PNG, once it is there.
    pub fn denoised_png(&self) -> Option<Vec<u8>> {
        let state = self.state();
        state.picture.as_ref()?.denoised.as_ref().map(|denoised| denoised.png.clone())
    }

    /// Runs `f` on the picture (to save it).
    pub fn with_picture<T>(&self, f: impl FnOnce(&Picture) -> T) -> Option<T> {
        self.state().picture.as_ref().map(f)
    }

    /// The events that tell the page the state after version `seen`, and that state's version;
    /// waits for a change at most `wait` (`None` if there was none).
    pub fn events_after(&self, seen: u64, wait: Duration) -> Option<(u64, String)> {
        let state = self.state();
        let (state, _) = self
            .changed
            .wait_timeout_while(state, wait, |state| state.version <= seen)
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        (state.version > seen).then(|| (state.version, events(&state)))
    }
}

fn encode(image: &Image, tone_map: &ToneMap) -> Vec<u8> {
    let pixels = tonemap::quantise(&tonemap::tonemap(image, tone_map));
    let mut png = Vec::new();
    // Encoding into memory fails only on a size PNG cannot hold, which a film never has.
    crate::image::png::encode(&mut png, image.width, image.height, &pixels)
        .expect("a film's size fits a PNG");
    png
}

/// Server-Sent Events: the error's text (one `data:` line per line, which the page joins with
/// newlines), then the state as JSON.
fn events(state: &State) -> String {
    let mut text = String::new();
    if let Some(error) = &state.error {
        text.push_str("event: scene-error\n");
        for line in error.lines() {
            text.push_str(&format!("data: {line}\n"));
        }
        text.push('\n');
    }
    let picture = match &state.picture {
        Some(p) => format!(
            r#"{{"png":{},"denoised":{},"render":{},"glance":{},"spp":{},"target":{},"seconds":{:.3},"width":{},"height":{}}}"#,
            p.png_number,
            p.denoised.is_some(),
            p.render,
            p.glance,
            p.info.samples_per_pixel,
            p.target,
            p.info.seconds,
            p.size.0,
            p.size.1
        ),
        None => "null".to_string(),
    };
    text.push_str(&format!(
        "event: state\ndata: {{\"version\":{},\"denoising\":{},\"render\":{},\"error\":{},\"operator\":\"{}\",\"exposure\":{},\"picture\":{picture}}}\n\n",
        state.version,
        state.denoising,
        state.render,
        state.error.is_some(),
        state.tone_map.op,
        state.tone_map.exposure,
    ));
    text
}
