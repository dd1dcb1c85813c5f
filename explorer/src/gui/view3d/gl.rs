//! The OpenGL side of the 3-D view, drawn inside egui's glow renderer by a paint callback
//! ([`egui_glow::CallbackFn`]): one shader pair in GLSL 1.40 / GLSL ES 3.00 (desktop GL 3.1+ and
//! WebGL2), a depth buffer, Lambert shading with the face normal from the screen-space
//! derivatives of the view-space position (flat faces, no normals in the vertex buffer).
//!
//! One vertex buffer holds the surface vertices, then the interface and contact points, then
//! the moulds' triangles (placed by the frame's poses); it is uploaded only when [`Scene::version`] changes (a new frame, field or point
//! colouring), the index buffer only when the topology changes.

use super::super::frames::Topology;
use eframe::egui_glow;
use eframe::glow::{self, HasContext};
use std::sync::Arc;

/// A vertex: position relative to the view's centre [m] and an sRGB colour with alpha.
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub(super) struct Vertex {
    pub(super) pos: [f32; 3],
    pub(super) rgba: [u8; 4],
}

const VERTEX_BYTES: usize = std::mem::size_of::<Vertex>();

/// What one picture draws, built by the view when what it shows changes.
pub(super) struct Scene {
    /// Changes whenever `vertices` does.
    pub(super) version: u64,
    /// The run's triangles.
    pub(super) topology: Arc<Topology>,
    /// Surface vertices, then interface and contact points, then three vertices per mould
    /// triangle.
    pub(super) vertices: Vec<Vertex>,
    pub(super) surface: usize,
    pub(super) points: usize,
}

/// Per-picture values: the camera and the point size.
#[derive(Clone, Copy)]
pub(super) struct Uniforms {
    /// Projection × view, column-major.
    pub(super) mvp: [f32; 16],
    /// View, column-major.
    pub(super) view: [f32; 16],
    /// Diameter of the interface points [physical pixels].
    pub(super) point_size: f32,
}

const VERTEX_SHADER: &str = r#"
in vec3 a_pos;
in vec4 a_rgba;
uniform mat4 u_mvp;
uniform mat4 u_view;
uniform float u_point_size;
out vec3 v_view;
out vec4 v_rgba;
void main() {
    gl_Position = u_mvp * vec4(a_pos, 1.0);
    v_view = (u_view * vec4(a_pos, 1.0)).xyz;
    v_rgba = a_rgba;
    gl_PointSize = u_point_size;
}
"#;

/// `u_mode`: 0 lit faces (the surface; the moulds, see-through), 1 round points, 2 unlit.
const FRAGMENT_SHADER: &str = r#"
in vec3 v_view;
in vec4 v_rgba;
uniform int u_mode;
out vec4 o_colour;
void main() {
    vec3 c = v_rgba.rgb;
    if (u_mode == 0) {
        vec3 n = normalize(cross(dFdx(v_view), dFdy(v_view)));
        // Lambert, two-sided, a head light a little above and left of the eye.
        float l = abs(dot(n, normalize(vec3(-0.3, 0.4, 1.0))));
        c *= 0.3 + 0.7 * l;
    } else if (u_mode == 1) {
        vec2 d = gl_PointCoord - vec2(0.5);
        if (dot(d, d) > 0.25) discard;
    }
    o_colour = vec4(c, v_rgba.a);
}
"#;

/// The GL objects of the view, created in the first paint.
pub(super) struct GlView {
    program: glow::Program,
    vertex_array: glow::VertexArray,
    vbo: glow::Buffer,
    ibo: glow::Buffer,
    u_mvp: Option<glow::UniformLocation>,
    u_view: Option<glow::UniformLocation>,
    u_point_size: Option<glow::UniformLocation>,
    u_mode: Option<glow::UniformLocation>,
    /// Version of the uploaded vertices.
    uploaded: u64,
    /// The topology whose triangles are uploaded (held, so that its address is not reused).
    triangles: Option<Arc<Topology>>,
    /// Vertex buffer uploads so far.
    pub(super) uploads: u64,
}

unsafe fn compile(
    gl: &glow::Context,
    kind: u32,
    header: &str,
    src: &str,
) -> Result<glow::Shader, String> {
    unsafe {
        let s = gl.create_shader(kind)?;
        gl.shader_source(s, &format!("{header}{src}"));
        gl.compile_shader(s);
        if gl.get_shader_compile_status(s) {
            Ok(s)
        } else {
            Err(format!("3-D view shader: {}", gl.get_shader_info_log(s)))
        }
    }
}

impl GlView {
    /// Compiles the shaders (GLSL ES 3.00 on WebGL2/GLES, 1.40 on desktop GL) and makes the
    /// buffers; an error names what the context lacks.
    pub(super) fn new(gl: &glow::Context) -> Result<GlView, String> {
        let version = egui_glow::ShaderVersion::get(gl);
        if !version.is_new_shader_interface() {
            return Err(format!(
                "the 3-D view needs GLSL 1.40 or GLSL ES 3.00 (WebGL2); this context has {version:?}"
            ));
        }
        let header = format!("{}precision highp float;\n", version.version_declaration());
        unsafe {
            let program = gl.create_program()?;
            let vs = compile(gl, glow::VERTEX_SHADER, &header, VERTEX_SHADER)?;
            let fs = compile(gl, glow::FRAGMENT_SHADER, &header, FRAGMENT_SHADER)?;
            gl.attach_shader(program, vs);
            gl.attach_shader(program, fs);
            gl.bind_attrib_location(program, 0, "a_pos");
            gl.bind_attrib_location(program, 1, "a_rgba");
            gl.link_program(program);
            if !gl.get_program_link_status(program) {
                return Err(format!(
                    "3-D view shaders: {}",
                    gl.get_program_info_log(program)
                ));
            }
            for s in [vs, fs] {
                gl.detach_shader(program, s);
                gl.delete_shader(s);
            }
            let vertex_array = gl.create_vertex_array()?;
            let (vbo, ibo) = (gl.create_buffer()?, gl.create_buffer()?);
            gl.bind_vertex_array(Some(vertex_array));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(vbo));
            gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(ibo));
            let stride = VERTEX_BYTES as i32;
            gl.enable_vertex_attrib_array(0);
            gl.vertex_attrib_pointer_f32(0, 3, glow::FLOAT, false, stride, 0);
            gl.enable_vertex_attrib_array(1);
            gl.vertex_attrib_pointer_f32(1, 4, glow::UNSIGNED_BYTE, true, stride, 12);
            gl.bind_vertex_array(None);
            let u = |name| gl.get_uniform_location(program, name);
            Ok(GlView {
                program,
                vertex_array,
                vbo,
                ibo,
                u_mvp: u("u_mvp"),
                u_view: u("u_view"),
                u_point_size: u("u_point_size"),
                u_mode: u("u_mode"),
                uploaded: u64::MAX,
                triangles: None,
                uploads: 0,
            })
        }
    }

    /// Uploads what changed in `scene`.
    unsafe fn upload(&mut self, gl: &glow::Context, scene: &Scene) {
        unsafe {
            if self.uploaded != scene.version {
                // SAFETY: `Vertex` is `repr(C)` plain data (12 bytes of f32, 4 of u8, no padding).
                let bytes = std::slice::from_raw_parts(
                    scene.vertices.as_ptr().cast::<u8>(),
                    scene.vertices.len() * VERTEX_BYTES,
                );
                gl.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::DYNAMIC_DRAW);
                self.uploads += 1;
            }
            let t = &scene.topology;
            if !self.triangles.as_ref().is_some_and(|u| Arc::ptr_eq(u, t)) {
                let flat: Vec<u32> = t.triangles.iter().flatten().copied().collect();
                let bytes = std::slice::from_raw_parts(flat.as_ptr().cast::<u8>(), 4 * flat.len());
                gl.buffer_data_u8_slice(glow::ELEMENT_ARRAY_BUFFER, bytes, glow::STATIC_DRAW);
                self.triangles = Some(t.clone());
            }
            self.uploaded = scene.version;
        }
    }

    /// Draws `scene` in the callback's viewport (set by egui_glow), over what egui drew there.
    pub(super) fn paint(
        &mut self,
        gl: &glow::Context,
        info: &egui::PaintCallbackInfo,
        scene: &Scene,
        u: &Uniforms,
    ) {
        let vp = info.viewport_in_pixels();
        unsafe {
            gl.use_program(Some(self.program));
            gl.bind_vertex_array(Some(self.vertex_array));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.vbo));
            gl.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(self.ibo));
            self.upload(gl, scene);
            gl.enable(glow::SCISSOR_TEST);
            gl.scissor(vp.left_px, vp.from_bottom_px, vp.width_px, vp.height_px);
            gl.enable(glow::DEPTH_TEST);
            gl.depth_func(glow::LEQUAL);
            gl.depth_mask(true);
            gl.clear_depth_f32(1.0);
            gl.clear(glow::DEPTH_BUFFER_BIT);
            gl.disable(glow::BLEND);
            if !gl.version().is_embedded {
                gl.enable(glow::PROGRAM_POINT_SIZE);
            }
            gl.uniform_matrix_4_f32_slice(self.u_mvp.as_ref(), false, &u.mvp);
            gl.uniform_matrix_4_f32_slice(self.u_view.as_ref(), false, &u.view);
            gl.uniform_1_f32(self.u_point_size.as_ref(), u.point_size);
            gl.uniform_1_i32(self.u_mode.as_ref(), 0);
            let n = 3 * scene.topology.triangles.len() as i32;
            gl.draw_elements(glow::TRIANGLES, n, glow::UNSIGNED_INT, 0);
            gl.uniform_1_i32(self.u_mode.as_ref(), 1);
            gl.draw_arrays(glow::POINTS, scene.surface as i32, scene.points as i32);
            // The moulds: see-through, behind and in front of the body, lit so that a curved
            // one shows its shape.
            let first = scene.surface + scene.points;
            gl.enable(glow::BLEND);
            gl.blend_func(glow::SRC_ALPHA, glow::ONE_MINUS_SRC_ALPHA);
            gl.depth_mask(false);
            gl.uniform_1_i32(self.u_mode.as_ref(), 0);
            let quads = (scene.vertices.len() - first) as i32;
            gl.draw_arrays(glow::TRIANGLES, first as i32, quads);
            gl.depth_mask(true);
            gl.disable(glow::DEPTH_TEST);
            gl.bind_vertex_array(None);
        }
    }
}
