//! Frame timing: the wall time of each frame's drawing, and between frame starts (what the
//! user sees as the frame rate), as medians.

use std::collections::VecDeque;
use std::time::Instant;

/// Frames the panel's median frame time is taken over.
const RECENT: usize = 31;

#[derive(Default)]
pub(crate) struct FrameClock {
    recent_draw_ms: VecDeque<f64>,
    draw_ms: Vec<f64>,
    interval_ms: Vec<f64>,
    last_start: Option<Instant>,
}

impl FrameClock {
    /// A frame that started at `start` has been shown.
    pub(crate) fn shown(&mut self, start: Instant) {
        let ms = start.elapsed().as_secs_f64() * 1e3;
        if let Some(previous) = self.last_start {
            self.interval_ms
                .push((start - previous).as_secs_f64() * 1e3);
        }
        self.last_start = Some(start);
        self.draw_ms.push(ms);
        self.recent_draw_ms.push_back(ms);
        if self.recent_draw_ms.len() > RECENT {
            self.recent_draw_ms.pop_front();
        }
    }

    /// Median draw time of the last frames, milliseconds.
    pub(crate) fn recent_draw_ms(&mut self) -> Option<f64> {
        median(self.recent_draw_ms.make_contiguous())
    }

    /// Whether the recent frames fill their window (until then each frame moves the median).
    pub(crate) fn settled(&self) -> bool {
        self.recent_draw_ms.len() >= RECENT
    }

    /// Median draw time of every frame, milliseconds.
    pub(crate) fn draw_ms(&self) -> Option<f64> {
        median(&self.draw_ms)
    }

    /// Median time between the starts of consecutive frames, milliseconds.
    pub(crate) fn interval_ms(&self) -> Option<f64> {
        median(&self.interval_ms)
    }
}

fn median(values: &[f64]) -> Option<f64> {
    (!values.is_empty()).then(|| crate::stats::median(&mut values.to_vec()))
}
