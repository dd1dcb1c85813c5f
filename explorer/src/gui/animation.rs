//! The 3-D view as an animated GIF, for slides: the run's frames shown one after the other,
//! each captured by a screenshot of the window cropped to the view, halved when wide, and
//! encoded with image-rs's `gif` (its NeuQuant palette per frame), 10 frames a second.

use super::App;
use egui::ColorImage;
use std::sync::{Arc, Mutex};

pub use crate::tunables::GIF_DELAY;
pub use crate::tunables::GIF_FRAMES;
use crate::tunables::GIF_MAX_WIDTH;

/// An animation being captured.
pub struct GifCapture {
    /// The view's frames to capture, in order.
    pub indices: Vec<usize>,
    /// How many are captured.
    pub next: usize,
    /// Where the window puts the screenshot asked for; `None` while none is asked.
    pub slot: Option<Arc<Mutex<Option<Arc<ColorImage>>>>>,
    pub images: Vec<ColorImage>,
    pub name: String,
}

/// `n` frame indices out of `total`, evenly spread, the first and the last included.
pub fn spread(total: usize, n: usize) -> Vec<usize> {
    match (total, n.min(total)) {
        (0, _) | (_, 0) => vec![],
        (_, 1) => vec![total - 1],
        (_, n) => (0..n).map(|k| k * (total - 1) / (n - 1)).collect(),
    }
}

/// `image` halved (each pixel the mean of a 2 × 2 block) until it is at most `max` wide.
pub fn shrink(image: ColorImage, max: usize) -> ColorImage {
    let mut image = image;
    while image.size[0] > max && image.size[1] >= 2 {
        let [w, h] = [image.size[0] / 2, image.size[1] / 2];
        let at = |x: usize, y: usize| image.pixels[y * image.size[0] + x];
        let mut pixels = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let q = [
                    at(2 * x, 2 * y),
                    at(2 * x + 1, 2 * y),
                    at(2 * x, 2 * y + 1),
                    at(2 * x + 1, 2 * y + 1),
                ];
                let mean = |c: usize| {
                    let sum: u32 = q.iter().map(|p| p.to_array()[c] as u32).sum();
                    ((sum + 2) / 4) as u8
                };
                pixels.push(egui::Color32::from_rgba_premultiplied(
                    mean(0),
                    mean(1),
                    mean(2),
                    mean(3),
                ));
            }
        }
        image = ColorImage::new([w, h], pixels);
    }
    image
}

/// The frames as a looping GIF, `delay` hundredths of a second each; all of one size.
pub fn encode_gif(frames: &[ColorImage], delay: u16) -> Result<Vec<u8>, String> {
    let Some(first) = frames.first() else {
        return Err("no frame to encode".into());
    };
    let [w, h] = first.size;
    let (w16, h16) = (u16::try_from(w), u16::try_from(h));
    let (Ok(w16), Ok(h16)) = (w16, h16) else {
        return Err(format!("{w} × {h} pixels: a GIF is at most 65535 a side"));
    };
    let mut bytes = Vec::new();
    {
        let mut encoder =
            gif::Encoder::new(&mut bytes, w16, h16, &[]).map_err(|e| e.to_string())?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(|e| e.to_string())?;
        for image in frames {
            if image.size != first.size {
                return Err("the frames differ in size".into());
            }
            let mut rgba: Vec<u8> = (image.pixels.iter())
                .flat_map(|c| c.to_srgba_unmultiplied())
                .collect();
            let mut frame = gif::Frame::from_rgba_speed(w16, h16, &mut rgba, 10);
            frame.delay = delay;
            encoder.write_frame(&frame).map_err(|e| e.to_string())?;
        }
    }
    Ok(bytes)
}

impl App {
    /// Starts capturing the run's frames as an animation (none while one is being captured or
    /// without frames).
    pub(super) fn start_gif(&mut self) {
        let total = self.view.frames().len();
        if self.gif.is_some() || total == 0 {
            return;
        }
        self.view.playing = false;
        self.gif = Some(GifCapture {
            indices: spread(total, GIF_FRAMES),
            next: 0,
            slot: None,
            images: vec![],
            name: format!("{}_3d_view.gif", self.settings.scene_stem()),
        });
    }

    /// One step of the capture, after the view is drawn: shows the next frame and asks for its
    /// screenshot, takes a screenshot that came, and at the end encodes and saves the GIF.
    pub(super) fn gif_step(&mut self, ctx: &egui::Context) {
        let Some(g) = &mut self.gif else {
            return;
        };
        let Some(rect) = self.view.rect else {
            return;
        };
        if let Some(slot) = &g.slot {
            let Some(image) = slot.lock().ok().and_then(|mut s| s.take()) else {
                ctx.request_repaint();
                return;
            };
            let region = image.region(&rect, Some(ctx.pixels_per_point()));
            g.images.push(shrink(region, GIF_MAX_WIDTH));
            g.next += 1;
            g.slot = None;
        }
        if let Some(&index) = g.indices.get(g.next) {
            // Shown now, captured at the end of the next frame drawn.
            self.view.shown = Some(index);
            let slot: Arc<Mutex<Option<Arc<ColorImage>>>> = Default::default();
            let fill = slot.clone();
            let repaint = ctx.clone();
            ctx.request_screenshot(move |shot| {
                if let Ok(mut s) = fill.lock() {
                    *s = Some(shot);
                }
                repaint.request_repaint();
            });
            g.slot = Some(slot);
            return;
        }
        let g = self.gif.take().expect("checked above");
        match encode_gif(&g.images, GIF_DELAY) {
            Ok(bytes) => self.save_file(&g.name, &bytes),
            Err(e) => self
                .notes
                .push(format!("{}: cannot encode the GIF: {e}", g.name)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_spread_evenly_with_both_ends() {
        assert_eq!(spread(201, 5), [0, 50, 100, 150, 200]);
        assert_eq!(spread(3, 60), [0, 1, 2]);
        assert_eq!(spread(7, 1), [6]);
        assert!(spread(0, 60).is_empty());
    }

    /// Two 4 × 2 frames halved to 2 × 1 (the 2 × 2 blocks' means) and encoded: the GIF decodes
    /// to two frames of that size, the delay and the colours kept (a two-colour image needs no
    /// approximation by the palette).
    #[test]
    fn a_gif_reads_back() {
        let (r, b) = (egui::Color32::RED, egui::Color32::BLUE);
        let make = |left, right| {
            ColorImage::new(
                [4, 2],
                vec![left, left, right, right, left, left, right, right],
            )
        };
        let frames: Vec<ColorImage> = [make(r, b), make(b, r)]
            .into_iter()
            .map(|f| shrink(f, 2))
            .collect();
        assert_eq!(frames[0].size, [2, 1]);
        assert_eq!(frames[0].pixels, [r, b]);
        let bytes = encode_gif(&frames, GIF_DELAY).unwrap();
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::RGBA);
        let mut decoder = options.read_info(std::io::Cursor::new(bytes)).unwrap();
        let mut seen = vec![];
        while let Some(f) = decoder.read_next_frame().unwrap() {
            assert_eq!((f.width, f.height, f.delay), (2, 1, GIF_DELAY));
            seen.push(f.buffer.to_vec());
        }
        assert_eq!(
            seen,
            [
                vec![255, 0, 0, 255, 0, 0, 255, 255],
                vec![0, 0, 255, 255, 255, 0, 0, 255]
            ]
        );
    }
}
