//! `raydiance preview`: a page served on this machine that shows a scene's render as it
//! refines, and renders the scene again as soon as it or a file it reads is saved.
//!
//! Threads share what the page shows (`Shown`): the renderer loads and renders, publishing each
//! finished pass (and, built with `denoise`, the pass denoised) or the scene's error; the
//! watcher polls the files the last load read; the server answers the page, each event stream
//! on a thread of its own.

mod renderer;
mod server;
mod shown;
mod watch;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

use crate::denoise::{DenoiseError, Denoiser};
use crate::{LoadError, RenderRequest};
pub use server::MAX_STREAMS;
use server::Site;
use shown::Shown;
use watch::{POLL, Watch};

/// Where the preview listens unless told: this machine only.
pub const DEFAULT_LISTEN: &str = "127.0.0.1:7420";

/// What to preview.
#[derive(Debug, Clone)]
pub struct Preview {
    pub scene: PathBuf,
    pub request: RenderRequest,
}

#[derive(Debug, thiserror::Error)]
pub enum PreviewError {
    #[error(transparent)]
    Scene(#[from] LoadError),
    #[error("error: cannot listen on {address}: {message}")]
    Listen { address: SocketAddr, message: String },
}

/// A preview listening, not yet serving.
pub struct Server {
    http: tiny_http::Server,
    address: SocketAddr,
    preview: Preview,
}

/// Binds `address` for `preview` (port 0: any free port); the scene must exist, its errors
/// are shown in the page.
pub fn listen(preview: Preview, address: SocketAddr) -> Result<Server, PreviewError> {
    crate::lang::check_readable(&preview.scene).map_err(LoadError::from)?;
    let http = tiny_http::Server::http(address)
        .map_err(|e| PreviewError::Listen { address, message: e.to_string() })?;
    let address = http.server_addr().to_ip().unwrap_or(address);
    Ok(Server { http, address, preview })
}

impl Server {
    pub fn address(&self) -> SocketAddr {
        self.address
    }

    pub fn url(&self) -> String {
        format!("http://{}/", self.address)
    }

    /// Serves and renders until the process ends; the render runs on the calling thread (and
    /// so on the rayon pool it is in, `--threads`).
    pub fn serve(self) -> ! {
        let denoiser = match Denoiser::new() {
            Ok(denoiser) => Some(denoiser),
            Err(DenoiseError::NotBuilt) => None,
            Err(error) => {
                eprintln!("{error}: the preview shows its passes as they are");
                None
            }
        };
        let shown = Arc::new(Shown::new(denoiser.is_some()));
        let watch = Arc::new(Watch::default());
        let watcher = watch.clone();
        std::thread::spawn(move || {
            loop {
                watcher.poll();
                std::thread::sleep(POLL);
            }
        });
        let site = Arc::new(Site::new(&self.preview.scene, self.address, denoiser.is_some()));
        let served = shown.clone();
        std::thread::spawn(move || {
            for request in self.http.incoming_requests() {
                let (shown, site) = (served.clone(), site.clone());
                std::thread::spawn(move || server::respond(request, &shown, &site));
            }
        });
        let (scene, request) = (&self.preview.scene, &self.preview.request);
        renderer::run(scene, request, &shown, &watch, denoiser.as_ref())
    }
}
