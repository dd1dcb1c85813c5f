//! The browser's services the explorer and the web page ([`crate::web`]) use (wasm32 only):
//! the page's document, the console, a download.

use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// The page's document.
pub fn document() -> Result<web_sys::Document, String> {
    web_sys::window()
        .and_then(|w| w.document())
        .ok_or_else(|| "no document".to_string())
}

/// Writes `text` to the browser's console.
pub fn log(text: &str) {
    web_sys::console::log_1(&text.into());
}

/// A JavaScript error as text.
pub fn js_text(e: JsValue) -> String {
    e.as_string().unwrap_or_else(|| format!("{e:?}"))
}

/// Saves `bytes` as the file `name` through the browser (a download).
pub fn download(name: &str, bytes: &[u8]) -> Result<(), String> {
    let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
    download_parts(name, &parts, "application/octet-stream")
}

/// A download of the blob made of `parts`, of MIME type `kind`.
fn download_parts(name: &str, parts: &js_sys::Array, kind: &str) -> Result<(), String> {
    let options = web_sys::BlobPropertyBag::new();
    options.set_type(kind);
    let blob =
        web_sys::Blob::new_with_u8_array_sequence_and_options(parts, &options).map_err(js_text)?;
    let url = web_sys::Url::create_object_url_with_blob(&blob).map_err(js_text)?;
    let link = document()?
        .create_element("a")
        .map_err(js_text)?
        .dyn_into::<web_sys::HtmlAnchorElement>()
        .map_err(|_| "cannot make a link")?;
    link.set_href(&url);
    link.set_download(name);
    link.click();
    web_sys::Url::revoke_object_url(&url).map_err(js_text)
}
