//! The frame loop: xrWaitFrame (paces nothing: it returns at once),
//! xrBeginFrame, xrEndFrame (validates submitted projection layers, and
//! captures a view when the script asks) and xrLocateViews (stereo views
//! from the scripted head pose); the frame statistics written at the end.

use ash::vk;
use openxr_sys as sys;
use sys::Handle as _;

use crate::api_instance::check_stereo;
use crate::api_session::{sess, session_of};
use crate::api_spaces::{all_valid, tracked, untracked, world_pose};
use crate::api_swapchain::two_call;
use crate::script::{pose, FrameStats, Script};
use crate::state::{InstanceData, SessionData, SpaceKind};
use crate::{done, input, output, with_rt};

const HALF_IPD: f32 = 0.032;
const HALF_FOV: f32 = std::f32::consts::FRAC_PI_4;

/// Writes the frame statistics to the script's `stats_path`.
pub(crate) fn write_stats(script: &Script, s: &SessionData) {
    if let Some(p) = &script.stats_path {
        let stats = FrameStats {
            frames_ended: s.frame.ended,
            projection_layers: s.frame.projection_layers,
            graphics: s.graphics,
            haptics: s.haptics,
        };
        if let Ok(t) = serde_json::to_string(&stats) {
            let _ = std::fs::write(p, t);
        }
    }
}

fn renders(state: sys::SessionState) -> bool {
    state == sys::SessionState::VISIBLE || state == sys::SessionState::FOCUSED
}

pub(crate) unsafe extern "system" fn wait_frame(
    session: sys::Session,
    _info: *const sys::FrameWaitInfo,
    state: *mut sys::FrameState,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let state = match unsafe { output(state) } {
        Ok(s) => s,
        Err(e) => return e,
    };
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            let s = session_of(i);
            if !s.running {
                return Err(sys::Result::ERROR_SESSION_NOT_RUNNING);
            }
            s.frame.waited = true;
            let period = 11_111_111;
            state.predicted_display_period = sys::Duration::from_nanos(period);
            state.predicted_display_time =
                sys::Time::from_nanos(crate::api_session::now().as_nanos() + period);
            state.should_render = renders(s.state).into();
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn begin_frame(
    session: sys::Session,
    _info: *const sys::FrameBeginInfo,
) -> sys::Result {
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            let s = session_of(i);
            if !s.running {
                return Err(sys::Result::ERROR_SESSION_NOT_RUNNING);
            }
            if !s.frame.waited {
                return Err(sys::Result::ERROR_CALL_ORDER_INVALID);
            }
            s.frame.waited = false;
            if s.frame.begun {
                return Ok(sys::Result::FRAME_DISCARDED);
            }
            s.frame.begun = true;
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn end_frame(
    session: sys::Session,
    info: *const sys::FrameEndInfo,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let info = match unsafe { input(info) } {
        Ok(i) => i,
        Err(e) => return e,
    };
    let mut layers = Vec::new();
    for k in 0..info.layer_count as usize {
        if info.layers.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: `layers` holds layer_count pointers to layer structs.
        let l = unsafe { *info.layers.add(k) };
        if l.is_null() {
            return sys::Result::ERROR_LAYER_INVALID;
        }
        // SAFETY: every layer starts with the base header.
        if unsafe { (*l).ty } != sys::CompositionLayerProjection::TYPE {
            return sys::Result::ERROR_LAYER_INVALID;
        }
        // SAFETY: its type says it is a projection layer.
        let p = unsafe { &*(l as *const sys::CompositionLayerProjection) };
        if p.view_count != 2 || p.views.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: `views` holds view_count (2) projection views.
        let views = unsafe { [*p.views, *p.views.add(1)] };
        layers.push((p.space.into_raw(), views));
    }
    with_rt(|rt| {
        let capture_path = rt.script.capture_path.clone();
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::FrameEndInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if !session_of(i).frame.begun {
                return Err(sys::Result::ERROR_CALL_ORDER_INVALID);
            }
            if info.display_time.as_nanos() <= 0 {
                return Err(sys::Result::ERROR_TIME_INVALID);
            }
            if info.environment_blend_mode != sys::EnvironmentBlendMode::OPAQUE {
                return Err(sys::Result::ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED);
            }
            for (space, views) in &layers {
                if !i.spaces.contains_key(space) {
                    return Err(sys::Result::ERROR_HANDLE_INVALID);
                }
                for v in views {
                    let sc = i
                        .swapchains
                        .get(&v.sub_image.swapchain.into_raw())
                        .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
                    if !sc.released_once {
                        return Err(sys::Result::ERROR_LAYER_INVALID);
                    }
                    if v.sub_image.image_array_index >= sc.array_size {
                        return Err(sys::Result::ERROR_VALIDATION_FAILURE);
                    }
                    let r = v.sub_image.image_rect;
                    if r.offset.x < 0
                        || r.offset.y < 0
                        || r.extent.width <= 0
                        || r.extent.height <= 0
                        || (r.offset.x + r.extent.width) as u32 > sc.width
                        || (r.offset.y + r.extent.height) as u32 > sc.height
                    {
                        return Err(sys::Result::ERROR_SWAPCHAIN_RECT_INVALID);
                    }
                    let q = v.pose.orientation;
                    let n = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
                    if !(n - 1.0).abs().lt(&0.01) {
                        return Err(sys::Result::ERROR_POSE_INVALID);
                    }
                }
            }
            if let (Some(path), Some((_, views))) = (capture_path.as_ref(), layers.first()) {
                capture(i, &views[0], path);
            }
            let n = layers.len() as u64;
            let s = session_of(i);
            s.frame.begun = false;
            s.frame.ended += 1;
            s.frame.projection_layers += n;
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn locate_views(
    session: sys::Session,
    info: *const sys::ViewLocateInfo,
    state: *mut sys::ViewState,
    capacity: u32,
    count: *mut u32,
    views: *mut sys::View,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, state) = match unsafe { (input(info), output(state)) } {
        (Ok(i), Ok(s)) => (i, s),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let profile = rt.script.profile.clone();
        let current = rt.script.live(rt.step);
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::ViewLocateInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            check_stereo(info.view_configuration_type)?;
            if info.display_time.as_nanos() <= 0 {
                return Err(sys::Result::ERROR_TIME_INVALID);
            }
            let base = *i
                .spaces
                .get(&info.space.into_raw())
                .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
            let frame = session_of(i).synced.clone().unwrap_or(current);
            crate::api_spaces::settle_local_origin(i, &frame);
            let head = crate::state::SpaceInfo {
                session: session.into_raw(),
                kind: SpaceKind::Reference(sys::ReferenceSpaceType::VIEW),
                offset: ([0.0; 3], [0.0, 0.0, 0.0, 1.0]),
            };
            let located = match (
                world_pose(i, &profile, &frame, &head),
                world_pose(i, &profile, &frame, &base),
            ) {
                (Some((h, nh)), Some((b, nb))) => {
                    Some((pose::compose(pose::inverse(b), h), nh || nb))
                }
                _ => None,
            };
            let fov = sys::Fovf {
                angle_left: -HALF_FOV,
                angle_right: HALF_FOV,
                angle_up: HALF_FOV,
                angle_down: -HALF_FOV,
            };
            let out: Vec<sys::View> = [-HALF_IPD, HALF_IPD]
                .iter()
                .map(|dx| sys::View {
                    ty: sys::View::TYPE,
                    next: std::ptr::null_mut(),
                    pose: match located {
                        Some((h, nan)) => tracked(
                            pose::compose(h, ([*dx, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0])),
                            nan,
                        ),
                        None => untracked(),
                    },
                    fov,
                })
                .collect();
            state.view_state_flags = if located.is_some() {
                let f = all_valid();
                sys::ViewStateFlags::from_raw(f.into_raw())
            } else {
                sys::ViewStateFlags::EMPTY
            };
            // SAFETY: forwarded caller pointers.
            Ok(unsafe { two_call(&out, capacity, count, views) })
        }))
    })
}

/// Copies the layer a projection view shows (its swapchain's last released
/// image, its array index) into a file: 8-byte header (width, height as
/// little-endian u32) then RGBA8 rows. Once per process; failures are
/// reported on stderr and leave no file.
fn capture(i: &mut InstanceData, view: &sys::CompositionLayerProjectionView, path: &str) {
    let Some(v) = i.vulkan.as_ref() else { return };
    if v.captured {
        return;
    }
    let (Some(vi), Some(d)) = (v.instance.as_ref(), v.device.as_ref()) else {
        return;
    };
    let Some(sc) = i.swapchains.get(&view.sub_image.swapchain.into_raw()) else {
        return;
    };
    let Some(&(image, _)) = sc.images.get(sc.last_released) else {
        return;
    };
    let (w, h, layer) = (sc.width, sc.height, view.sub_image.image_array_index);
    let bgra = sc.format == vk::Format::B8G8R8A8_SRGB;
    let size = u64::from(w) * u64::from(h) * 4;
    // SAFETY: every handle is live on the app's device; the app released
    // the image (its rendering was waited for), the runtime owns the copy's
    // resources and waits for the queue before freeing them.
    let r = unsafe {
        (|| -> Result<Vec<u8>, vk::Result> {
            let queue = d.get_device_queue(v.queue_family, 0);
            let pool = d.create_command_pool(
                &vk::CommandPoolCreateInfo::default().queue_family_index(v.queue_family),
                None,
            )?;
            let buf = d.create_buffer(
                &vk::BufferCreateInfo::default()
                    .size(size)
                    .usage(vk::BufferUsageFlags::TRANSFER_DST),
                None,
            )?;
            let req = d.get_buffer_memory_requirements(buf);
            let props = vi.get_physical_device_memory_properties(v.physical_device);
            let want =
                vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
            let t = (0..props.memory_type_count)
                .find(|&t| {
                    req.memory_type_bits & (1 << t) != 0
                        && props.memory_types[t as usize].property_flags.contains(want)
                })
                .ok_or(vk::Result::ERROR_FEATURE_NOT_PRESENT)?;
            let mem = d.allocate_memory(
                &vk::MemoryAllocateInfo::default()
                    .allocation_size(req.size)
                    .memory_type_index(t),
                None,
            )?;
            d.bind_buffer_memory(buf, mem, 0)?;
            let cmd = d.allocate_command_buffers(
                &vk::CommandBufferAllocateInfo::default()
                    .command_pool(pool)
                    .level(vk::CommandBufferLevel::PRIMARY)
                    .command_buffer_count(1),
            )?[0];
            d.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
            let range = vk::ImageSubresourceRange {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                base_mip_level: 0,
                level_count: 1,
                base_array_layer: 0,
                layer_count: sc.array_size,
            };
            let to_src = vk::ImageMemoryBarrier::default()
                .image(image)
                .old_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
                .dst_access_mask(vk::AccessFlags::TRANSFER_READ)
                .subresource_range(range);
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[to_src],
            );
            let region = vk::BufferImageCopy {
                image_subresource: vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: layer,
                    layer_count: 1,
                },
                image_extent: vk::Extent3D {
                    width: w,
                    height: h,
                    depth: 1,
                },
                ..Default::default()
            };
            d.cmd_copy_image_to_buffer(
                cmd,
                image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buf,
                &[region],
            );
            let back = vk::ImageMemoryBarrier::default()
                .image(image)
                .old_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                .new_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .src_access_mask(vk::AccessFlags::TRANSFER_READ)
                .subresource_range(range);
            d.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[back],
            );
            d.end_command_buffer(cmd)?;
            let cmds = [cmd];
            d.queue_submit(
                queue,
                &[vk::SubmitInfo::default().command_buffers(&cmds)],
                vk::Fence::null(),
            )?;
            d.queue_wait_idle(queue)?;
            let p = d.map_memory(mem, 0, size, vk::MemoryMapFlags::empty())?;
            let bytes = std::slice::from_raw_parts(p as *const u8, size as usize).to_vec();
            d.unmap_memory(mem);
            d.destroy_command_pool(pool, None);
            d.destroy_buffer(buf, None);
            d.free_memory(mem, None);
            Ok(bytes)
        })()
    };
    match r {
        Ok(mut bytes) => {
            if bgra {
                bytes.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
            }
            let mut out = Vec::with_capacity(bytes.len() + 8);
            out.extend_from_slice(&w.to_le_bytes());
            out.extend_from_slice(&h.to_le_bytes());
            out.extend_from_slice(&bytes);
            if let Err(e) = std::fs::write(path, out) {
                eprintln!("shapewright-xr-testrt: writing {path}: {e}");
            }
        }
        Err(e) => eprintln!("shapewright-xr-testrt: capture failed: {e}"),
    }
    if let Some(v) = i.vulkan.as_mut() {
        v.captured = true;
    }
}
