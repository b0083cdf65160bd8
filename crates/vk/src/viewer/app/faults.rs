//! The viewer's frame preconditions: the faults injected by tests before a frame, and the
//! swapchain extent of a frame, with the recovery from a zero-sized or lost surface.

use std::time::Instant;

use ash::vk;
use winit::dpi::PhysicalSize;

use super::{App, REQUEST_SIZE_WAIT};
use crate::error::Result;
use crate::viewer::Fault;

impl App<'_> {
    /// Injects the [`ViewerOptions::faults`] due before this frame.
    pub(super) fn inject_faults(&mut self) {
        let (Some(window), Some(gpu)) = (self.window.as_ref(), self.gpu.as_mut()) else {
            return;
        };
        let now = Instant::now();
        if let Some((size, since)) = self.awaiting_size {
            if window.inner_size() != size && now.duration_since(since) < REQUEST_SIZE_WAIT {
                return;
            }
            self.awaiting_size = None;
        }
        let mut pressed = Vec::new();
        while let Some(&(frame, fault)) = self.faults.front()
            && frame <= self.report.frames
        {
            self.faults.pop_front();
            log::debug!("injecting {fault:?} before frame {frame}");
            match fault {
                Fault::RequestSize([w, h]) => {
                    let size = PhysicalSize::new(w, h);
                    let _ = window.request_inner_size(size);
                    self.awaiting_size = Some((size, now));
                    break;
                }
                Fault::Minimize => window.set_minimized(true),
                Fault::ZeroWindow(d) => self.zero_window_until = now.checked_add(d),
                Fault::ZeroSurface(d) => {
                    gpu.injected.zero_surface_until = now.checked_add(d);
                    gpu.swapchain_dirty = true;
                }
                Fault::Acquire(f) => gpu.injected.acquire.push_back(f),
                Fault::Present(f) => gpu.injected.present.push_back(f),
                Fault::Press(k) => pressed.push(k),
            }
        }
        for k in pressed {
            self.press(k);
        }
    }

    /// The swapchain extent for this frame, (re)creating the surface and the
    /// swapchain if needed; `None` before the window exists, while it or its
    /// surface is 0×0 (minimised) and while the surface is lost.
    pub(super) fn swapchain_extent(&mut self) -> Result<Option<vk::Extent2D>> {
        let Some(gpu) = self.gpu.as_mut() else {
            return Ok(None);
        };
        let Some(window) = self.window.as_ref() else {
            return Ok(None);
        };
        if gpu.surface_lost && !gpu.recreate_surface(window)? {
            self.dirty = true;
            return Ok(None);
        }
        let zero_window = self.zero_window_until.is_some_and(|t| Instant::now() < t);
        let size = if zero_window {
            PhysicalSize::new(0, 0)
        } else {
            window.inner_size()
        };
        let extent = if size.width == 0 || size.height == 0 {
            None
        } else {
            gpu.ensure_swapchain(size)?
        };
        if gpu.surface_lost {
            // Lost while (re)creating the swapchain: create the surface again at once.
            self.dirty = true;
            return Ok(None);
        }
        self.zero_extent = extent.is_none();
        if extent.is_some() {
            self.next_zero_check = None;
        }
        Ok(extent)
    }
}
