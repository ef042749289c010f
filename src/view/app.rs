//! The viewer's event loop: a winit window, a presenting device context made for it, a
//! [`Renderer`] drawing at the window's size and a [`Presenter`] putting each frame on screen.
//! Keys turn the [`Knobs`] (a new renderer for the new scene), the mouse and keys move the
//! [`CameraRig`], the title shows the [`Overlay`]. With a frame count it stops by itself after
//! that many presented frames and reads the last one back, which is how it is tested headless.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::Vec3;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::Key;
use winit::window::{Window, WindowId};

use super::camera_rig::{CameraRig, RigMode};
use super::controls::{action, fly_axis, Action, HELP};
use super::knobs::Knobs;
use super::overlay::Overlay;
use super::presenter::{Presented, Presenter, Screenshot};
use crate::heightfield::Heightfield;
use crate::render::{FrameOutput, FrameRequest, RenderError, RenderOptions, Renderer};
use crate::scene::Scene;
use crate::vk::{Context, ContextOptions, PresentMode, VkError, WindowHandles};

/// What `relief view` was asked to show, and how.
pub struct ViewSetup {
    /// The scene to show; its camera (or a framing of its bounds) is the first view.
    pub scene: Scene,
    /// The height map relief materials without their own read.
    pub heights: Option<Heightfield>,
    /// The window's first size and the height storage and addressing.
    pub options: RenderOptions,
    /// Which device and validation, as for an offscreen context.
    pub context: ContextOptions,
    /// Whether presenting waits for the display (`V` toggles it while running).
    pub present: PresentMode,
    /// Stop after this many presented frames (a headless run); `None` runs until closed.
    pub frames: Option<u64>,
    /// Where the last frame of a counted run is written.
    pub screenshot: Option<PathBuf>,
    /// Ask the window for another size once this many frames have been presented.
    pub resize_at: Option<(u64, (u32, u32))>,
}

/// How a view ended.
#[derive(Debug, Clone)]
pub struct ViewReport {
    /// The device that drew, as `Context::describe` says it.
    pub device: String,
    /// Frames presented.
    pub frames: u64,
    /// The last readout (fps and per-pass GPU times).
    pub readout: String,
    /// Validation errors and warnings the run caused, with the first few texts.
    pub validation_errors: u32,
    /// Warnings the validation layer reported.
    pub validation_warnings: u32,
    /// The first few of the validation layer's messages.
    pub validation_messages: Vec<String>,
    /// Whether the validation layer was loaded, so that zero errors means something.
    pub validation_enabled: bool,
}

/// Why the viewer stopped early.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    #[error("no display to open a window on ({0}); set DISPLAY, or run it under Xvfb (xvfb-run relief view ...)")]
    /// No window system could be reached (no `DISPLAY`, or its libraries are missing).
    NoDisplay(String),
    #[error("the window: {0}")]
    /// The window system refused to open the window or to run its event loop.
    Window(String),
    #[error(transparent)]
    /// Preparing or drawing the scene failed.
    Render(#[from] RenderError),
    #[error(transparent)]
    /// A Vulkan call failed: no device that can present, surface or swapchain errors, a lost
    /// device.
    Vulkan(#[from] VkError),
    #[error("the window did not take the size {0}x{1} asked for within {2} s")]
    /// A scripted resize (width, height) did not reach the window within the seconds given.
    ResizeIgnored(u32, u32, u64),
    #[error("writing {path}: {source}")]
    /// A screenshot could not be written.
    Screenshot {
        /// The PNG it was to be written to.
        path: PathBuf,
        /// Why the encoder or the file system refused it.
        source: image::ImageError,
    },
}

/// How long a scripted resize may take to reach the window.
const RESIZE_PATIENCE: Duration = Duration::from_secs(10);

/// Opens the window and runs until it is closed, Esc is pressed, or the frame count is reached.
pub fn run(setup: ViewSetup) -> Result<ViewReport, ViewError> {
    let event_loop = EventLoop::new().map_err(|e| ViewError::NoDisplay(e.to_string()))?;
    let mut app = App {
        setup,
        running: None,
        outcome: Ok(()),
        report: None,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| ViewError::Window(e.to_string()))?;
    if let Some(running) = app.running.take() {
        app.report = Some(running.close());
    }
    app.outcome?;
    app.report
        .ok_or_else(|| ViewError::Window("the window never opened".into()))
}

struct App {
    setup: ViewSetup,
    running: Option<Running>,
    outcome: Result<(), ViewError>,
    report: Option<ViewReport>,
}

/// Everything that lives while the window is open. Field order is drop order: the objects that
/// hold the device context go first, the context next, the window it presents to last.
struct Running {
    gpu: Gpu,
    ctx: Arc<Context>,
    window: Window,
    base: Scene,
    knobs: Knobs,
    rig: CameraRig,
    overlay: Overlay,
    device: String,
    frames: u64,
    /// A scripted resize on its way: the size and when it was asked for.
    pending_resize: Option<((u32, u32), Instant)>,
    /// Fly keys held, as (right, up, forward).
    fly: Vec3,
    dragging: Option<(f64, f64)>,
    cursor: (f64, f64),
    last_frame: Instant,
    screenshot_next: bool,
    screenshots: u32,
}

struct Gpu {
    presenter: Presenter,
    renderer: Renderer,
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match Running::open(event_loop, &self.setup) {
            Ok(running) => self.running = Some(running),
            Err(e) => self.stop(event_loop, Err(e)),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(running) = self.running.as_mut() else {
            return;
        };
        let result = match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => {
                self.stop(event_loop, Ok(()));
                return;
            }
            WindowEvent::RedrawRequested => running.frame(&self.setup),
            WindowEvent::KeyboardInput { event, .. } => running.key(&event, &self.setup),
            WindowEvent::MouseInput { state, button, .. } => {
                if button == MouseButton::Left {
                    running.dragging = (state == ElementState::Pressed).then_some(running.cursor);
                }
                Ok(Flow::Continue)
            }
            WindowEvent::CursorMoved { position, .. } => {
                running.cursor = (position.x, position.y);
                if let Some((x, y)) = running.dragging {
                    running
                        .rig
                        .drag((position.x - x) as f32, (position.y - y) as f32);
                    running.dragging = Some(running.cursor);
                }
                Ok(Flow::Continue)
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                running.rig.zoom(steps);
                Ok(Flow::Continue)
            }
            _ => Ok(Flow::Continue),
        };
        match result {
            Ok(Flow::Continue) => {}
            Ok(Flow::Done) => self.stop(event_loop, Ok(())),
            Err(e) => self.stop(event_loop, Err(e)),
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(running) = &self.running {
            running.window.request_redraw();
        }
    }
}

impl App {
    /// Ends the loop with `outcome`; the first failure wins.
    fn stop(&mut self, event_loop: &ActiveEventLoop, outcome: Result<(), ViewError>) {
        if self.outcome.is_ok() {
            self.outcome = outcome;
        }
        event_loop.exit();
    }
}

/// Whether the loop goes on after an event.
enum Flow {
    Continue,
    Done,
}

impl Running {
    fn open(event_loop: &ActiveEventLoop, setup: &ViewSetup) -> Result<Running, ViewError> {
        let size = PhysicalSize::new(setup.options.width, setup.options.height);
        let attributes = Window::default_attributes()
            .with_title("relief")
            .with_inner_size(size);
        let window = event_loop
            .create_window(attributes)
            .map_err(|e| ViewError::Window(e.to_string()))?;
        let handles = WindowHandles {
            display: window
                .display_handle()
                .map_err(|e| ViewError::Window(e.to_string()))?
                .as_raw(),
            window: window
                .window_handle()
                .map_err(|e| ViewError::Window(e.to_string()))?
                .as_raw(),
        };
        // SAFETY: `Running` declares the window after everything holding the context, so the
        // window outlives the context (see `close` for the explicit order).
        let ctx = unsafe { Context::new_presenting(&setup.context, &handles) }?;
        let device = ctx.info().name.clone();
        eprintln!("device: {}", ctx.describe());
        let inner = window.inner_size();
        let presenter = Presenter::new(&ctx, (inner.width, inner.height), setup.present)?;
        let (width, height) = presenter.extent();
        let options = RenderOptions {
            width,
            height,
            ..setup.options.clone()
        };
        let renderer = Renderer::new(&ctx, &setup.scene, setup.heights.as_ref(), &options)?;
        let center = setup
            .scene
            .bounds()
            .map_or(Vec3::ZERO, |(lo, hi)| (lo + hi) * 0.5);
        let rig = CameraRig::new(renderer.default_camera(), center);
        if setup.frames.is_none() {
            println!("{HELP}");
        }
        let now = Instant::now();
        let running = Running {
            gpu: Gpu {
                presenter,
                renderer,
            },
            ctx,
            window,
            base: setup.scene.clone(),
            knobs: Knobs::default(),
            rig,
            overlay: Overlay::new(now),
            device,
            frames: 0,
            pending_resize: None,
            fly: Vec3::ZERO,
            dragging: None,
            cursor: (0.0, 0.0),
            last_frame: now,
            screenshot_next: false,
            screenshots: 0,
        };
        running.show_title();
        Ok(running)
    }

    /// Draws and presents one frame, follows the window's size, counts the frame.
    fn frame(&mut self, setup: &ViewSetup) -> Result<Flow, ViewError> {
        let inner = self.window.inner_size();
        if inner.width == 0 || inner.height == 0 {
            return Ok(Flow::Continue); // minimised
        }
        let window = (inner.width, inner.height);
        self.follow_resize(setup, window)?;
        let gpu = &mut self.gpu;
        if gpu.presenter.extent() != window {
            gpu.presenter.rebuild(window, gpu.presenter.mode())?;
        }
        let (width, height) = gpu.presenter.extent();
        for done in gpu.renderer.resize(width, height)? {
            self.overlay.add(&done.timings);
        }
        let now = Instant::now();
        let seconds = now.duration_since(self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        self.rig.fly(self.fly, seconds);
        let request = FrameRequest {
            camera: self.rig.camera(),
            read_back: false,
        };
        if let Some(done) = gpu.renderer.submit(&request)? {
            self.overlay.add(&done.timings);
        }
        let last = self.pending_resize.is_none() && setup.frames == Some(self.frames + 1);
        let capture = last || self.screenshot_next;
        let color = gpu.renderer.color_target();
        let shot = match gpu.presenter.present(color, window, capture)? {
            Presented::Dropped => return Ok(Flow::Continue),
            Presented::Shown(shot) => shot,
        };
        if self.pending_resize.is_none() {
            self.frames += 1;
        }
        if let Some(shot) = shot {
            self.save_shot(&shot, last, setup)?;
        }
        if let Some(line) = self.overlay.refresh(now) {
            log::debug!("{line}");
            self.show_title();
        }
        Ok(if last { Flow::Done } else { Flow::Continue })
    }

    /// Asks for the scripted size when its frame comes, and waits (not counting frames) until
    /// the window has it.
    fn follow_resize(&mut self, setup: &ViewSetup, window: (u32, u32)) -> Result<(), ViewError> {
        if let Some((at, size)) = setup.resize_at {
            if self.frames == at && self.pending_resize.is_none() && window != size {
                let _ = self
                    .window
                    .request_inner_size(PhysicalSize::new(size.0, size.1));
                self.pending_resize = Some((size, Instant::now()));
            }
        }
        let Some((size, asked)) = self.pending_resize else {
            return Ok(());
        };
        if window == size {
            self.pending_resize = None;
        } else if asked.elapsed() > RESIZE_PATIENCE {
            return Err(ViewError::ResizeIgnored(
                size.0,
                size.1,
                RESIZE_PATIENCE.as_secs(),
            ));
        }
        Ok(())
    }

    fn note(&mut self, done: FrameOutput) {
        self.overlay.add(&done.timings);
    }

    fn save_shot(
        &mut self,
        shot: &Screenshot,
        last: bool,
        setup: &ViewSetup,
    ) -> Result<(), ViewError> {
        let path = match (&setup.screenshot, last) {
            (Some(path), true) => path.clone(),
            (None, true) => return Ok(()),
            _ => {
                self.screenshot_next = false;
                self.screenshots += 1;
                PathBuf::from(format!("relief-view-{}.png", self.screenshots))
            }
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| ViewError::Screenshot {
                path: path.clone(),
                source: image::ImageError::IoError(e),
            })?;
        }
        image::save_buffer(
            &path,
            &shot.rgba,
            shot.width,
            shot.height,
            image::ColorType::Rgba8,
        )
        .map_err(|source| ViewError::Screenshot {
            path: path.clone(),
            source,
        })?;
        eprintln!("wrote {} ({}x{})", path.display(), shot.width, shot.height);
        Ok(())
    }

    fn key(&mut self, event: &KeyEvent, setup: &ViewSetup) -> Result<Flow, ViewError> {
        let pressed = event.state == ElementState::Pressed;
        if let Some((axis, sign)) = fly_axis(&event.logical_key) {
            self.fly[axis] = if pressed { sign } else { 0.0 };
            return Ok(Flow::Continue);
        }
        if !pressed || event.repeat && !matches!(event.logical_key, Key::Character(_)) {
            return Ok(Flow::Continue);
        }
        let Some(act) = action(&event.logical_key) else {
            return Ok(Flow::Continue);
        };
        let before = self.knobs.clone();
        match act {
            Action::Quit => return Ok(Flow::Done),
            Action::Help => println!("{HELP}"),
            Action::ToggleRig => {
                self.rig.toggle_mode();
                let mode = match self.rig.mode() {
                    RigMode::Orbit => "orbit",
                    RigMode::Fly => "fly (W/S, A/D, R/F)",
                };
                eprintln!("camera: {mode}");
            }
            Action::ResetCamera => self.rig.reset(),
            Action::CycleMethod(step) => self.knobs.cycle_method(&self.base, step),
            Action::CycleShadows => self.knobs.cycle_shadows(&self.base),
            Action::CycleAo => self.knobs.cycle_ao(&self.base),
            Action::ToggleLod => self.knobs.toggle_lod(&self.base),
            Action::ScaleDepth(f) => self.knobs.scale_depth(f),
            Action::ToggleVsync => {
                let mode = match self.gpu.presenter.mode() {
                    PresentMode::Vsync => PresentMode::Unpaced,
                    PresentMode::Unpaced => PresentMode::Vsync,
                };
                let size = self.gpu.presenter.extent();
                self.gpu.presenter.rebuild(size, mode)?;
                eprintln!("present mode: {:?}", self.gpu.presenter.present_mode());
            }
            Action::Screenshot => self.screenshot_next = true,
        }
        if self.knobs != before {
            self.rebuild_renderer(setup, before)?;
        }
        Ok(Flow::Continue)
    }

    /// A renderer for the scene the knobs now make; if it cannot be made, the knobs go back to
    /// `before` and the old renderer stays.
    fn rebuild_renderer(&mut self, setup: &ViewSetup, before: Knobs) -> Result<(), ViewError> {
        let scene = self.knobs.apply(&self.base);
        self.window.set_title(&format!(
            "relief | building {}",
            self.knobs.describe(&self.base)
        ));
        for done in self.gpu.renderer.finish()? {
            self.note(done);
        }
        let (width, height) = self.gpu.presenter.extent();
        let options = RenderOptions {
            width,
            height,
            ..setup.options.clone()
        };
        let started = Instant::now();
        match Renderer::new(&self.ctx, &scene, setup.heights.as_ref(), &options) {
            Ok(renderer) => {
                self.gpu.renderer = renderer;
                eprintln!(
                    "{} (ready in {:.1} s)",
                    self.knobs.describe(&self.base),
                    started.elapsed().as_secs_f64()
                );
            }
            Err(RenderError::Vulkan(e @ VkError::DeviceLost { .. })) => return Err(e.into()),
            Err(e) => {
                eprintln!(
                    "relief view: cannot show {}: {e}",
                    self.knobs.describe(&self.base)
                );
                self.knobs = before;
            }
        }
        self.show_title();
        Ok(())
    }

    fn show_title(&self) {
        self.window.set_title(&format!(
            "relief | {} | {} | {} | F1 help",
            self.device,
            self.knobs.describe(&self.base),
            self.overlay.line()
        ));
    }

    /// Waits for the GPU, tears down in order and reports what validation said.
    fn close(self) -> ViewReport {
        let Running {
            gpu,
            ctx,
            window,
            mut overlay,
            device,
            frames,
            ..
        } = self;
        let Gpu {
            presenter,
            mut renderer,
        } = gpu;
        // The frames still in flight count too, and a short bounded run may end before the
        // readout's first refresh: the report names the passes all the same.
        if let Ok(done) = renderer.finish() {
            for frame in &done {
                overlay.add(&frame.timings);
            }
        }
        overlay.flush(Instant::now());
        drop(presenter);
        drop(renderer);
        let _ = ctx.wait_idle();
        let messages = ctx.messages();
        let report = ViewReport {
            device,
            frames,
            readout: overlay.line().to_owned(),
            validation_errors: messages.errors(),
            validation_warnings: messages.warnings(),
            validation_messages: messages.kept_messages(),
            validation_enabled: ctx.validation_enabled(),
        };
        drop(ctx);
        drop(window);
        report
    }
}
