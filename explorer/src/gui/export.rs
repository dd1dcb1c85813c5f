//! Figures for slides: a plot as PNG (a screenshot of the window cropped to it), SVG or CSV
//! ([`crate::figure`]), the 3-D view as PNG; files in the output folder natively, downloads in
//! the page.

use super::App;
use crate::figure::Figure;
use egui::ColorImage;
use std::sync::{Arc, Mutex};

/// What a right-click on a plot asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Export {
    /// The plot's rectangle on the screen [points].
    Png(egui::Rect),
    Svg,
    Csv,
}

/// A screenshot asked for and not yet received: the file's name, the rectangle to keep, and
/// where the window puts the picture when it has read it.
#[derive(Clone)]
pub struct PendingPng {
    pub name: String,
    pub rect: egui::Rect,
    pub image: Arc<Mutex<Option<Arc<ColorImage>>>>,
}

/// `image` as a PNG file (8-bit RGBA).
pub fn encode_png(image: &ColorImage) -> Result<Vec<u8>, String> {
    let [w, h] = image.size;
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w as u32, h as u32);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    let data: Vec<u8> = (image.pixels.iter())
        .flat_map(|c| c.to_srgba_unmultiplied())
        .collect();
    writer.write_image_data(&data).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// A file name from a plot's title: letters and digits, the rest as `_`.
pub fn file_stem(title: &str) -> String {
    let s: String = (title.chars())
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let s = s.split('_').filter(|p| !p.is_empty()).collect::<Vec<_>>();
    s.join("_").chars().take(60).collect()
}

impl App {
    /// Carries out `what` for the figure `fig`: SVG and CSV at once, PNG at the next frame
    /// (the screenshot comes with it).
    pub(super) fn export_figure(&mut self, ctx: &egui::Context, fig: &Figure, what: Export) {
        let name = file_stem(&fig.title);
        match what {
            Export::Svg => self.save_file(&format!("{name}.svg"), fig.svg().as_bytes()),
            Export::Csv => self.save_file(&format!("{name}.csv"), fig.csv().as_bytes()),
            Export::Png(rect) => self.request_png(ctx, &name, rect),
        }
    }

    /// Asks the window for a screenshot, to be cropped to `rect` and saved as `name.png`.
    pub(super) fn request_png(&mut self, ctx: &egui::Context, name: &str, rect: egui::Rect) {
        let image: Arc<Mutex<Option<Arc<ColorImage>>>> = Default::default();
        let slot = image.clone();
        let repaint = ctx.clone();
        ctx.request_screenshot(move |shot| {
            if let Ok(mut s) = slot.lock() {
                *s = Some(shot);
            }
            repaint.request_repaint();
        });
        self.pending_png = Some(PendingPng {
            name: format!("{name}.png"),
            rect,
            image,
        });
    }

    /// Takes the screenshot asked for, when it has come: cropped and saved.
    pub(super) fn take_screenshot(&mut self, ctx: &egui::Context) {
        let Some(p) = &self.pending_png else {
            return;
        };
        let Some(image) = p.image.lock().ok().and_then(|mut s| s.take()) else {
            return;
        };
        let p = self.pending_png.take().expect("checked above");
        let region = image.region(&p.rect, Some(ctx.pixels_per_point()));
        match encode_png(&region) {
            Ok(bytes) => self.save_file(&p.name, &bytes),
            Err(e) => self
                .notes
                .push(format!("{}: cannot encode the PNG: {e}", p.name)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 2 image encoded and decoded back by the png crate: the same size and pixels.
    #[test]
    fn a_png_reads_back() {
        let colours = [
            egui::Color32::RED,
            egui::Color32::GREEN,
            egui::Color32::BLUE,
            egui::Color32::WHITE,
            egui::Color32::BLACK,
            egui::Color32::from_rgb(12, 34, 56),
        ];
        let image = ColorImage::new([3, 2], colours.to_vec());
        let bytes = encode_png(&image).unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (3, 2));
        let want: Vec<u8> = colours
            .iter()
            .flat_map(|c| c.to_srgba_unmultiplied())
            .collect();
        assert_eq!(&buf[..info.buffer_size()], &want[..]);
    }

    #[test]
    fn file_stems_are_plain() {
        assert_eq!(
            file_stem("run 3: force on the pulled faces [N]"),
            "run_3_force_on_the_pulled_faces_N"
        );
    }
}
