//! winit's events: the window's lifecycle, keys, and the mouse's orbit and zoom.

use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, StartCause, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::WindowId;

use super::capture::timestamped;
use super::compare::{Compare, View};
use super::{edit, orbit, App};

/// How near the wipe's split line (in pixels, either side) a press grabs it instead of
/// orbiting.
pub(crate) const SPLIT_GRAB_PX: f64 = 8.0;

impl App {
    /// Keys that act on the scene (egui has not taken the keyboard).
    fn key(&mut self, event_loop: &ActiveEventLoop, code: KeyCode) {
        match code {
            // An open menu (a combo box's list) closes first: egui closes it on this key
            // at the next frame. So does one a click on the panel is about to open: on a
            // slow frame the click and the key can both wait for the same frame, and the
            // menu is not open yet when the key arrives.
            KeyCode::Escape
                if self.panel_press_undrawn || egui::Popup::is_any_open(&self.egui_ctx) => {}
            KeyCode::Escape => event_loop.exit(),
            KeyCode::KeyM => edit::toggle_term(&mut self.scene),
            KeyCode::KeyF => {
                let on = !edit::is_furnace(&self.scene);
                edit::set_furnace(&mut self.scene, on, &mut self.controls.saved_lighting);
            }
            KeyCode::KeyS => self.screenshot = Some(timestamped("png")),
            KeyCode::KeyE => self.pending.exr = Some(timestamped("exr")),
            _ => return,
        }
        self.request_redraw();
    }

    fn pointer(&mut self, event: &WindowEvent) {
        match *event {
            WindowEvent::CursorMoved { position, .. } => {
                let (x, y) = (position.x, position.y);
                if let (true, Some(c)) = (self.split_drag, &mut self.controls.compare) {
                    c.split = Compare::split_at(x, self.scene_width);
                    self.request_redraw();
                } else if let Some((px, py)) = self.drag {
                    let (dx, dy) = (x - px, y - py);
                    self.scene.camera = orbit::orbit(
                        &self.scene.camera,
                        -dx * orbit::RADIANS_PER_PIXEL,
                        dy * orbit::RADIANS_PER_PIXEL,
                    );
                    self.drag = Some((x, y));
                    self.request_redraw();
                }
                self.cursor = (x, y);
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                let in_scene = self.cursor.0 < self.scene_width as f64;
                let down = state == ElementState::Pressed;
                self.panel_press_undrawn |= down && !in_scene;
                let pressed = down && in_scene;
                let on_split = self.controls.compare.is_some_and(|c| {
                    c.view == View::Wipe
                        && (self.cursor.0 - c.split_px(self.scene_width) as f64).abs()
                            <= SPLIT_GRAB_PX
                });
                self.split_drag = pressed && on_split;
                self.drag = (pressed && !on_split).then_some(self.cursor);
            }
            WindowEvent::MouseWheel { delta, .. } if self.cursor.0 < self.scene_width as f64 => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y as f64,
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                self.scene.camera = orbit::zoom(&self.scene.camera, lines, self.home_distance);
                self.request_redraw();
            }
            _ => {}
        }
    }
}

thread_local! {
    /// Set while a redraw runs: a panic then is reported to [`gone_while_drawing`] by the
    /// viewer's panic hook instead of printed, if it is winit's.
    static DRAWING: std::cell::Cell<Option<bool>> = const { std::cell::Cell::new(None) };
}

/// The source file of winit's X11 window, whose size query unwraps the `BadWindow` error of
/// a window destroyed from outside (winit 0.30: `inner_size_physical`).
const WINIT_X11_WINDOW: &str = "platform_impl/linux/x11/window.rs";

/// Runs `draw`; whether it panicked in winit's X11 window queries, which happens when the
/// window was destroyed from outside (`xdotool windowclose`) while a redraw was already
/// queued, before winit reports `Destroyed`. That panic is not printed. Any other panic
/// goes on as it would have (printed by the default hook, then unwound further).
fn gone_while_drawing(draw: impl FnOnce()) -> bool {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let winit = info
                .location()
                .is_some_and(|l| l.file().replace('\\', "/").ends_with(WINIT_X11_WINDOW));
            let drawing = DRAWING.with(|d| d.get()).is_some();
            if drawing && winit {
                DRAWING.with(|d| d.set(Some(true)));
            } else {
                previous(info);
            }
        }));
    });
    DRAWING.with(|d| d.set(Some(false)));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(draw));
    let in_winit = DRAWING.with(|d| d.replace(None)) == Some(true);
    match result {
        Ok(()) => false,
        Err(_) if in_winit => true,
        Err(payload) => std::panic::resume_unwind(payload),
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_none() {
            if let Err(e) = self.open(event_loop) {
                self.fail(event_loop, e);
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        if event == WindowEvent::Destroyed {
            // Destroyed from outside (`xdotool windowclose`, a crashed window manager):
            // nothing may ask the window anything again (winit's X11 size query unwraps the
            // error and panics, issue 28, 11): drop it and quit.
            self.state = None;
            event_loop.exit();
            return;
        }
        let Some(state) = &mut self.state else {
            return;
        };
        let response = match &mut self.egui_winit {
            Some(egui_winit) => egui_winit.on_window_event(&state.window, &event),
            None => return,
        };
        // egui asks to repaint after every event, the redraw itself included: that one
        // must not schedule another, or the window redraws forever.
        if response.repaint && event != WindowEvent::RedrawRequested {
            state.window.request_redraw();
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                state.resize(size.width, size.height);
                state.window.request_redraw();
            }
            WindowEvent::ScaleFactorChanged { .. } => state.window.request_redraw(),
            WindowEvent::RedrawRequested => {
                if gone_while_drawing(|| self.redraw(event_loop)) {
                    // As `WindowEvent::Destroyed` below: the window is gone, quit.
                    self.state = None;
                    event_loop.exit();
                }
            }
            // Synthetic presses are winit's report of keys already held when the window
            // gains focus (after a map, say): not a press of the user's.
            WindowEvent::KeyboardInput {
                event,
                is_synthetic: false,
                ..
            } if !response.consumed
                && !self.egui_ctx.egui_wants_keyboard_input()
                && event.state == ElementState::Pressed
                && !event.repeat =>
            {
                if let PhysicalKey::Code(code) = event.physical_key {
                    self.key(event_loop, code);
                }
            }
            // A map file dropped on the window lights the balls (as the panel's field).
            WindowEvent::DroppedFile(path) => {
                super::panel::load_map(&mut self.scene, &mut self.controls, &path);
                self.request_redraw();
            }
            // Not egui's `consumed`: that reflects where the pointer was at the last frame;
            // `pointer` itself keeps to the scene area.
            ref pointer => self.pointer(pointer),
        }
    }

    fn new_events(&mut self, event_loop: &ActiveEventLoop, cause: StartCause) {
        // egui's deadline (a blinking cursor, a tooltip's delay): redraw, then wait again
        // until something asks (a `WaitUntil` left in place would wake at once forever).
        if let StartCause::ResumeTimeReached { .. } = cause {
            event_loop.set_control_flow(ControlFlow::Wait);
            self.request_redraw();
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        // `--frames`: draw back to back until done.
        if self.options.frames.is_some_and(|n| self.frames_drawn < n) {
            self.request_redraw();
        }
    }
}
