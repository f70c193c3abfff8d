//! Statistical 3D human body models (S-SCAPE): a safe API over the sscape C library.
//!
//! A [`Model`] is immutable and shared (`Send + Sync`, cheap to clone: the C object is reference
//! counted); a [`Body`] and a [`Fitter`] belong to one thread at a time (`Send`) and keep their model
//! alive, so they may outlive the `Model` value they were made from. Every failed call is an
//! [`Error`] carrying the C status and the library's message. Units: metres and kilograms;
//! right-handed, Y up, the body facing +Z; quaternions x y z w. The raw declarations are
//! [`sys`] (the `sscape-sys` crate); `include/sscape/sscape.h` documents every function.
use std::ffi::{c_void, CStr, CString};
use std::fmt;
use std::os::raw::{c_char, c_int};
use std::path::Path;
use std::ptr::{self, NonNull};

pub use sscape_sys as sys;

/// The C API major version this crate is written for; the loaded library must have the same.
pub const ABI_MAJOR: u32 = sys::SSC_VERSION_MAJOR;

/// A failed call: the `ssc_status` value, its name and the library's message (`ssc_last_error`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    /// The `ssc_status` value (negative), e.g. `sys::SSC_ERROR_NOT_FOUND`.
    pub status: sys::ssc_status,
    /// What was wrong, from the library (or from this crate, for checks made before the call).
    pub message: String,
}

impl Error {
    /// The status's name, e.g. `"SSC_ERROR_NOT_FOUND"`.
    pub fn code(&self) -> &'static str {
        // Safety: ssc_status_name returns a static string for any value.
        unsafe { CStr::from_ptr(sys::ssc_status_name(self.status)) }.to_str().unwrap_or("SSC_ERROR_UNKNOWN")
    }

    fn invalid(message: String) -> Error {
        Error { status: sys::SSC_ERROR_INVALID_ARGUMENT, message }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.code(), self.message)
    }
}

impl std::error::Error for Error {}

/// The result of every fallible call.
pub type Result<T> = std::result::Result<T, Error>;

fn check(status: sys::ssc_status) -> Result<()> {
    if status == sys::SSC_OK {
        return Ok(());
    }
    // Safety: ssc_last_error returns the calling thread's message, valid until its next call.
    let message = unsafe { CStr::from_ptr(sys::ssc_last_error()) }.to_string_lossy().into_owned();
    Err(Error { status, message })
}

fn c_string(text: &str, what: &str) -> Result<CString> {
    CString::new(text).map_err(|_| Error::invalid(format!("{} contains a NUL byte", what)))
}

fn count_of(values: &[f32], per_item: usize, items: usize, what: &str) -> Result<()> {
    if values.len() != per_item * items {
        return Err(Error::invalid(format!("{}: {} values where {} are needed", what, values.len(), per_item * items)));
    }
    Ok(())
}

fn u32_len(len: usize, what: &str) -> Result<u32> {
    u32::try_from(len).map_err(|_| Error::invalid(format!("{}: {} is too many", what, len)))
}

/// The loaded library's version as (major, minor, patch).
pub fn version() -> (u32, u32, u32) {
    // Safety: no arguments.
    let number = unsafe { sys::ssc_version() };
    (number / 10000, number / 100 % 100, number % 100)
}

fn check_abi() -> Result<()> {
    // Safety: no arguments.
    abi_matches(unsafe { sys::ssc_version() })
}

/// Whether a library of version `number` (as `ssc_version` gives it) is one this crate may call.
fn abi_matches(number: u32) -> Result<()> {
    if number / 10000 != ABI_MAJOR {
        return Err(Error {
            status: sys::SSC_ERROR_UNSUPPORTED_VERSION,
            message: format!("the loaded libsscape is version {}; this crate is for ABI major {}", number, ABI_MAJOR),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    // A library of another major is refused (the dynamic loader refuses most first: the soname
    // carries the major).
    #[test]
    fn other_abi_majors_are_refused() {
        let next = (super::ABI_MAJOR + 1) * 10000;
        let e = super::abi_matches(next).unwrap_err();
        assert_eq!(e.status, super::sys::SSC_ERROR_UNSUPPORTED_VERSION);
        assert!(e.message.contains(&format!("ABI major {}", super::ABI_MAJOR)), "{}", e.message);
        assert!(super::abi_matches(super::ABI_MAJOR * 10000 + 99).is_ok());
    }
}

/// One of the library's measurements.
#[derive(Clone, Debug)]
pub struct Measurement {
    pub name: String,
    /// `"metre"`, `"square_metre"`, `"cubic_metre"` or `"kilogram"`.
    pub unit: &'static str,
    pub definition: String,
}

/// The measurements the library knows, in the order of [`Body::measure`].
pub fn measurements() -> Result<Vec<Measurement>> {
    // Safety: no arguments.
    let count = unsafe { sys::ssc_measurement_count() };
    let mut list = Vec::with_capacity(count as usize);
    for index in 0..count {
        let mut name: *const c_char = ptr::null();
        let mut definition: *const c_char = ptr::null();
        let mut unit: sys::ssc_unit = 0;
        // Safety: the outputs are valid; the strings are static.
        check(unsafe { sys::ssc_measurement_get_info(index, &mut name, &mut unit, &mut definition) })?;
        let unit = match unit {
            sys::SSC_UNIT_METRE => "metre",
            sys::SSC_UNIT_SQUARE_METRE => "square_metre",
            sys::SSC_UNIT_CUBIC_METRE => "cubic_metre",
            _ => "kilogram",
        };
        list.push(Measurement {
            name: unsafe { CStr::from_ptr(name) }.to_string_lossy().into_owned(),
            unit,
            definition: unsafe { CStr::from_ptr(definition) }.to_string_lossy().into_owned(),
        });
    }
    Ok(list)
}

/// A loaded model: immutable and shareable across threads.
pub struct Model {
    raw: NonNull<sys::ssc_model>,
}

// Safety: the C API documents a model as immutable after load and safe to use from any thread;
// its reference count is atomic.
unsafe impl Send for Model {}
unsafe impl Sync for Model {}

impl Clone for Model {
    fn clone(&self) -> Model {
        // Safety: raw is a live model.
        unsafe { sys::ssc_model_retain(self.raw.as_ptr()) };
        Model { raw: self.raw }
    }
}

impl Drop for Model {
    fn drop(&mut self) {
        // Safety: this value holds one reference.
        unsafe { sys::ssc_model_release(self.raw.as_ptr()) };
    }
}

/// The counts a body or fitter needs, read once from its model.
#[derive(Clone, Debug)]
struct Counts {
    vertices: usize,
    joints: usize,
    shapes: usize,
    landmarks: usize,
    level_vertices: Vec<usize>,
}

impl Model {
    fn from_out(load: impl FnOnce(*mut *mut sys::ssc_model) -> sys::ssc_status) -> Result<Model> {
        check_abi()?;
        let mut raw: *mut sys::ssc_model = ptr::null_mut();
        check(load(&mut raw))?;
        NonNull::new(raw).map(|raw| Model { raw }).ok_or_else(|| Error { status: sys::SSC_ERROR_INTERNAL, message: "no model".into() })
    }

    /// The default model built into the library.
    pub fn load_default() -> Result<Model> {
        // Safety: a NULL context is the default one; out is valid.
        Model::from_out(|out| unsafe { sys::ssc_model_load_default(ptr::null_mut(), out) })
    }

    /// A `.sscape` file, verified before use.
    pub fn load(path: impl AsRef<Path>) -> Result<Model> {
        let path = path.as_ref();
        let text = path.to_str().ok_or_else(|| Error::invalid(format!("{} is not UTF-8", path.display())))?;
        let c_path = c_string(text, "the path")?;
        // Safety: c_path outlives the call.
        Model::from_out(|out| unsafe { sys::ssc_model_load_file(ptr::null_mut(), c_path.as_ptr(), out) })
    }

    /// A `.sscape` file's bytes (copied).
    pub fn from_bytes(bytes: &[u8]) -> Result<Model> {
        // Safety: bytes is valid for its length.
        Model::from_out(|out| unsafe {
            sys::ssc_model_load_memory(ptr::null_mut(), bytes.as_ptr() as *const c_void, bytes.len(), out)
        })
    }

    /// The raw handle, for calls through [`sys`]; valid while this value lives.
    pub fn as_ptr(&self) -> *mut sys::ssc_model {
        self.raw.as_ptr()
    }

    pub fn vertex_count(&self) -> usize {
        unsafe { sys::ssc_model_vertex_count(self.raw.as_ptr()) as usize }
    }
    pub fn triangle_count(&self) -> usize {
        unsafe { sys::ssc_model_triangle_count(self.raw.as_ptr()) as usize }
    }
    pub fn joint_count(&self) -> usize {
        unsafe { sys::ssc_model_joint_count(self.raw.as_ptr()) as usize }
    }
    pub fn shape_count(&self) -> usize {
        unsafe { sys::ssc_model_shape_count(self.raw.as_ptr()) as usize }
    }
    pub fn landmark_count(&self) -> usize {
        unsafe { sys::ssc_model_landmark_count(self.raw.as_ptr()) as usize }
    }

    fn counts(&self) -> Counts {
        let level_vertices = self.levels().map(|levels| levels.iter().map(|l| l.vertex_count).collect()).unwrap_or_default();
        Counts {
            vertices: self.vertex_count(),
            joints: self.joint_count(),
            shapes: self.shape_count(),
            landmarks: self.landmark_count(),
            level_vertices,
        }
    }

    /// 3 vertex indices per triangle.
    pub fn triangles(&self) -> Result<Vec<u32>> {
        let mut out = vec![0u32; self.triangle_count() * 3];
        check(unsafe { sys::ssc_model_get_triangles(self.raw.as_ptr(), out.as_mut_ptr(), self.triangle_count() as u32) })?;
        Ok(out)
    }

    fn names(&self, count: usize, get: unsafe extern "C" fn(*const sys::ssc_model, u32, *mut *const c_char) -> sys::ssc_status) -> Result<Vec<String>> {
        (0..count as u32)
            .map(|index| {
                let mut name: *const c_char = ptr::null();
                check(unsafe { get(self.raw.as_ptr(), index, &mut name) })?;
                // Safety: the string belongs to the model, alive here.
                Ok(unsafe { CStr::from_ptr(name) }.to_string_lossy().into_owned())
            })
            .collect()
    }

    /// Joint names, in joint order.
    pub fn joint_names(&self) -> Result<Vec<String>> {
        self.names(self.joint_count(), sys::ssc_model_get_joint_name)
    }

    /// Landmark names (CAESAR names in the default model), in landmark order.
    pub fn landmark_names(&self) -> Result<Vec<String>> {
        self.names(self.landmark_count(), sys::ssc_model_get_landmark_name)
    }

    /// A joint's index; `SSC_ERROR_NOT_FOUND` for an unknown name.
    pub fn joint_index(&self, name: &str) -> Result<usize> {
        let c_name = c_string(name, "the joint name")?;
        let mut index = 0u32;
        check(unsafe { sys::ssc_model_find_joint(self.raw.as_ptr(), c_name.as_ptr(), &mut index) })?;
        Ok(index as usize)
    }

    /// A landmark's index; `SSC_ERROR_NOT_FOUND` for an unknown name.
    pub fn landmark_index(&self, name: &str) -> Result<usize> {
        let c_name = c_string(name, "the landmark name")?;
        let mut index = 0u32;
        check(unsafe { sys::ssc_model_find_landmark(self.raw.as_ptr(), c_name.as_ptr(), &mut index) })?;
        Ok(index as usize)
    }

    /// The levels of detail, in index order: 0 the full mesh (`"full"`), then the model's, finest first.
    pub fn levels(&self) -> Result<Vec<Level>> {
        let count = unsafe { sys::ssc_model_level_count(self.raw.as_ptr()) };
        (0..count)
            .map(|index| {
                let mut info = sys::ssc_level_info {
                    struct_size: std::mem::size_of::<sys::ssc_level_info>() as u32,
                    name: ptr::null(),
                    vertex_count: 0,
                    triangle_count: 0,
                    uv_count: 0,
                };
                check(unsafe { sys::ssc_model_get_level_info(self.raw.as_ptr(), index, &mut info) })?;
                // Safety: the name belongs to the model, alive here.
                let name = unsafe { CStr::from_ptr(info.name) }.to_string_lossy().into_owned();
                Ok(Level {
                    index: index as usize,
                    name,
                    vertex_count: info.vertex_count as usize,
                    triangle_count: info.triangle_count as usize,
                    uv_count: info.uv_count as usize,
                })
            })
            .collect()
    }

    /// A level's triangles, 3 vertex indices each.
    pub fn level_triangles(&self, level: usize) -> Result<Vec<u32>> {
        let levels = self.levels()?;
        let l = levels.get(level).ok_or_else(|| Error::invalid(format!("level {} of a model with {} levels", level, levels.len())))?;
        let mut out = vec![0u32; l.triangle_count * 3];
        check(unsafe { sys::ssc_model_get_level_triangles(self.raw.as_ptr(), level as u32, out.as_mut_ptr(), l.triangle_count as u32) })?;
        Ok(out)
    }

    /// The segment shape spaces (head, arm_l, ...; none in a model without them), in index order.
    pub fn segments(&self) -> Result<Vec<Segment>> {
        let count = unsafe { sys::ssc_model_segment_count(self.raw.as_ptr()) };
        (0..count)
            .map(|index| {
                let mut info = sys::ssc_segment_info {
                    struct_size: std::mem::size_of::<sys::ssc_segment_info>() as u32,
                    name: ptr::null(),
                    shape_count: 0,
                    vertex_count: 0,
                };
                check(unsafe { sys::ssc_model_get_segment_info(self.raw.as_ptr(), index, &mut info) })?;
                // Safety: the name belongs to the model, alive here.
                let name = unsafe { CStr::from_ptr(info.name) }.to_string_lossy().into_owned();
                Ok(Segment { name, shape_count: info.shape_count as usize, vertex_count: info.vertex_count as usize })
            })
            .collect()
    }

    /// A segment's index; `SSC_ERROR_NOT_FOUND` for a name the model lacks.
    pub fn segment_index(&self, name: &str) -> Result<usize> {
        let c_name = c_string(name, "the segment name")?;
        let mut index = 0u32;
        check(unsafe { sys::ssc_model_find_segment(self.raw.as_ptr(), c_name.as_ptr(), &mut index) })?;
        Ok(index as usize)
    }

    /// Standard deviation of each shape coefficient.
    pub fn shape_stddevs(&self) -> Result<Vec<f32>> {
        let mut out = vec![0f32; self.shape_count()];
        check(unsafe { sys::ssc_model_get_shape_stddevs(self.raw.as_ptr(), out.as_mut_ptr(), out.len() as u32) })?;
        Ok(out)
    }

    /// `count * shape_count` coefficients of random bodies of the population, reproducible by seed;
    /// each coefficient within `truncation` standard deviations.
    pub fn sample_shapes(&self, seed: u32, count: usize, truncation: f32) -> Result<Vec<f32>> {
        let mut out = vec![0f32; count * self.shape_count()];
        let capacity = u32_len(out.len(), "sample_shapes")?;
        check(unsafe {
            sys::ssc_model_sample_shapes(self.raw.as_ptr(), seed, u32_len(count, "sample_shapes")?, truncation, out.as_mut_ptr(), capacity)
        })?;
        Ok(out)
    }

    /// Many bodies in one call, in the rest pose or posed: `shapes` holds `count * shape_count`
    /// coefficients, `poses` (optional) `count * joint_count` quaternions, `translations` (optional)
    /// `count * 3`. Returns `count * vertex_count * 3` vertex coordinates, body after body.
    pub fn synthesize(&self, shapes: &[f32], poses: Option<&[f32]>, translations: Option<&[f32]>) -> Result<Vec<f32>> {
        self.synthesize_level(0, shapes, poses, translations)
    }

    /// `synthesize` for a level of detail (`levels`): `count * level vertex_count * 3` coordinates.
    pub fn synthesize_level(&self, level: usize, shapes: &[f32], poses: Option<&[f32]>, translations: Option<&[f32]>) -> Result<Vec<f32>> {
        let levels = self.levels()?;
        let v = levels.get(level).ok_or_else(|| Error::invalid(format!("synthesize: no level {level} (the model has {})", levels.len())))?.vertex_count;
        let (k, j) = (self.shape_count(), self.joint_count());
        if k == 0 || shapes.len() % k != 0 {
            return Err(Error::invalid(format!("synthesize: {} coefficients are not a whole number of bodies", shapes.len())));
        }
        let count = shapes.len() / k;
        if let Some(poses) = poses {
            count_of(poses, j * 4, count, "poses")?;
        }
        if let Some(translations) = translations {
            count_of(translations, 3, count, "translations")?;
        }
        let mut vertices = vec![0f32; count * v * 3];
        let mut desc = std::mem::MaybeUninit::<sys::ssc_batch_desc>::uninit();
        // Safety: ssc_batch_desc_init fills every field.
        let mut desc = unsafe {
            sys::ssc_batch_desc_init(desc.as_mut_ptr(), std::mem::size_of::<sys::ssc_batch_desc>());
            desc.assume_init()
        };
        desc.body_count = u32_len(count, "synthesize")?;
        desc.shapes = shapes.as_ptr();
        desc.shape_count = k as u32;
        desc.poses = poses.map_or(ptr::null(), |p| p.as_ptr());
        desc.translations = translations.map_or(ptr::null(), |t| t.as_ptr());
        desc.vertices = vertices.as_mut_ptr();
        desc.vertices_capacity = count * v;
        desc.level = level as u32;
        check(unsafe { sys::ssc_model_synthesize_batch(self.raw.as_ptr(), &desc) })?;
        Ok(vertices)
    }

    /// A new body of this model: mean shape, rest pose.
    pub fn body(&self) -> Result<Body> {
        let mut raw: *mut sys::ssc_body = ptr::null_mut();
        check(unsafe { sys::ssc_body_create(self.raw.as_ptr(), ptr::null(), &mut raw) })?;
        let raw = NonNull::new(raw).ok_or_else(|| Error { status: sys::SSC_ERROR_INTERNAL, message: "no body".into() })?;
        Ok(Body { raw, counts: self.counts() })
    }

    /// The fitter's settings with their defaults (`ssc_fitter_def_init`), to change and pass to [`Model::fitter`].
    pub fn fitter_def() -> sys::ssc_fitter_def {
        let mut def = std::mem::MaybeUninit::<sys::ssc_fitter_def>::uninit();
        // Safety: ssc_fitter_def_init fills every field.
        unsafe {
            sys::ssc_fitter_def_init(def.as_mut_ptr(), std::mem::size_of::<sys::ssc_fitter_def>());
            def.assume_init()
        }
    }

    /// A new fitter with the given settings (or the defaults).
    pub fn fitter(&self, def: Option<&sys::ssc_fitter_def>) -> Result<Fitter> {
        let mut raw: *mut sys::ssc_fitter = ptr::null_mut();
        check(unsafe { sys::ssc_fitter_create(self.raw.as_ptr(), def.map_or(ptr::null(), |d| d as *const _), &mut raw) })?;
        let raw = NonNull::new(raw).ok_or_else(|| Error { status: sys::SSC_ERROR_INTERNAL, message: "no fitter".into() })?;
        Ok(Fitter { raw, counts: self.counts() })
    }
}

/// A level of detail: 0 the full mesh, then the model's coarser meshes, finest first.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    pub index: usize,
    pub name: String,
    pub vertex_count: usize,
    pub triangle_count: usize,
    pub uv_count: usize,
}

/// `Body::write_level`'s level for every level of detail in one .glb file (a node each).
pub const ALL_LEVELS: usize = usize::MAX;

/// Shape morph targets in a .glb (`Body::write_with_morphs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Morphs {
    /// The first K whole-body components; weight 1 = +1 standard deviation.
    Components(usize),
    /// One per semantic slider; weight 1 = +1 population standard deviation of its attribute.
    Sliders,
}

/// A segment shape space: its name, components and the vertices they move.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    pub name: String,
    pub shape_count: usize,
    pub vertex_count: usize,
}

/// One body: shape and pose in, vertices and measurements out.
pub struct Body {
    raw: NonNull<sys::ssc_body>,
    counts: Counts,
}

// Safety: a body may move between threads; it is used by one at a time (&mut self for changes,
// and the C getters that cache results take the body mutably through &mut self too).
unsafe impl Send for Body {}

impl Drop for Body {
    fn drop(&mut self) {
        unsafe { sys::ssc_body_destroy(self.raw.as_ptr()) };
    }
}

impl Body {
    /// The raw handle, for calls through [`sys`].
    pub fn as_ptr(&mut self) -> *mut sys::ssc_body {
        self.raw.as_ptr()
    }

    /// Sets the first `coefficients.len()` shape coefficients (the rest 0).
    pub fn set_shape(&mut self, coefficients: &[f32]) -> Result<()> {
        check(unsafe { sys::ssc_body_set_shape(self.raw.as_ptr(), coefficients.as_ptr(), u32_len(coefficients.len(), "shape")?) })
    }

    /// The shape coefficients.
    pub fn shape(&self) -> Result<Vec<f32>> {
        let mut out = vec![0f32; self.counts.shapes];
        check(unsafe { sys::ssc_body_get_shape(self.raw.as_ptr(), out.as_mut_ptr(), out.len() as u32) })?;
        Ok(out)
    }

    /// The pose: `joint_count` quaternions (x y z w, relative to the parent) or `None` for the rest
    /// pose, and the root translation in metres.
    pub fn set_pose(&mut self, rotations: Option<&[f32]>, translation: Option<[f32; 3]>) -> Result<()> {
        if let Some(r) = rotations {
            count_of(r, 4, self.counts.joints, "rotations")?;
        }
        let t = translation.as_ref().map_or(ptr::null(), |t| t.as_ptr());
        let (r, n) = rotations.map_or((ptr::null(), 0), |r| (r.as_ptr(), self.counts.joints as u32));
        check(unsafe { sys::ssc_body_set_pose(self.raw.as_ptr(), r, n, t) })
    }

    /// As [`Body::set_pose`], each rotation an axis scaled by its angle in radians (3 per joint).
    pub fn set_pose_axis_angle(&mut self, rotations: &[f32], translation: Option<[f32; 3]>) -> Result<()> {
        count_of(rotations, 3, self.counts.joints, "rotations")?;
        let t = translation.as_ref().map_or(ptr::null(), |t| t.as_ptr());
        check(unsafe { sys::ssc_body_set_pose_axis_angle(self.raw.as_ptr(), rotations.as_ptr(), self.counts.joints as u32, t) })
    }

    fn points(&mut self, count: usize, get: unsafe extern "C" fn(*mut sys::ssc_body, *mut f32, u32, usize) -> sys::ssc_status) -> Result<Vec<f32>> {
        let mut out = vec![0f32; count * 3];
        check(unsafe { get(self.raw.as_ptr(), out.as_mut_ptr(), count as u32, 0) })?;
        Ok(out)
    }

    /// The posed vertices, `vertex_count * 3` coordinates in metres.
    pub fn vertices(&mut self) -> Result<Vec<f32>> {
        self.points(self.counts.vertices, sys::ssc_body_get_vertices)
    }

    /// Unit normals of the posed body, `vertex_count * 3`.
    pub fn normals(&mut self) -> Result<Vec<f32>> {
        self.points(self.counts.vertices, sys::ssc_body_get_normals)
    }

    /// The model's landmarks on the posed body, `landmark_count * 3`.
    pub fn landmarks(&mut self) -> Result<Vec<f32>> {
        self.points(self.counts.landmarks, sys::ssc_body_get_landmarks)
    }

    /// Every measurement, in the order of [`measurements`].
    pub fn measure(&mut self) -> Result<Vec<f32>> {
        let mut out = vec![0f32; unsafe { sys::ssc_measurement_count() } as usize];
        check(unsafe { sys::ssc_body_measure(self.raw.as_ptr(), out.as_mut_ptr(), out.len() as u32) })?;
        Ok(out)
    }

    /// One segment's coefficients ([`Model::segment_index`]), on top of the whole-body shape; the
    /// segment's remaining coefficients are set to 0.
    pub fn set_segment_shape(&mut self, segment: usize, coefficients: &[f32]) -> Result<()> {
        let segment = u32_len(segment, "the segment index")?;
        let count = u32_len(coefficients.len(), "set_segment_shape")?;
        check(unsafe { sys::ssc_body_set_segment_shape(self.raw.as_ptr(), segment, coefficients.as_ptr(), count) })
    }

    /// One segment's coefficients: `shape_count` of them ([`Segment::shape_count`]).
    pub fn segment_shape(&self, segment: usize, shape_count: usize) -> Result<Vec<f32>> {
        let segment = u32_len(segment, "the segment index")?;
        let mut out = vec![0f32; shape_count];
        check(unsafe { sys::ssc_body_get_segment_shape(self.raw.as_ptr(), segment, out.as_mut_ptr(), u32_len(out.len(), "segment_shape")?) })?;
        Ok(out)
    }

    /// One measurement by name (`"stature"`, `"waist_girth"`, ...).
    pub fn measure_by_name(&mut self, name: &str) -> Result<f32> {
        let c_name = c_string(name, "the measurement name")?;
        let mut value = 0f32;
        check(unsafe { sys::ssc_body_measure_by_name(self.raw.as_ptr(), c_name.as_ptr(), &mut value) })?;
        Ok(value)
    }

    /// Writes the posed body as OBJ, PLY or glTF binary, chosen by the file's extension.
    pub fn write(&mut self, path: impl AsRef<Path>) -> Result<()> {
        self.write_level(path, 0)
    }

    /// Writes a level of detail of the posed body (0 the full mesh; `ALL_LEVELS`: every level in one .glb).
    pub fn write_level(&mut self, path: impl AsRef<Path>, level: usize) -> Result<()> {
        let path = path.as_ref();
        let text = path.to_str().ok_or_else(|| Error::invalid(format!("{} is not UTF-8", path.display())))?;
        let c_path = c_string(text, "the path")?;
        let index = if level == ALL_LEVELS { u32::MAX } else { u32::try_from(level).map_err(|_| Error::invalid(format!("level {}", level)))? };
        check(unsafe { sys::ssc_body_write_level_file(self.raw.as_ptr(), index, c_path.as_ptr(), sys::SSC_FILE_FORMAT_BY_EXTENSION) })
    }

    /// Writes a .glb for engines: a level (or `ALL_LEVELS`) with shape morph targets (docs/engines.md);
    /// the joints' motion per unit of weight is in the file's `skins[0].extras.sscape_morphs`.
    pub fn write_with_morphs(&mut self, path: impl AsRef<Path>, level: usize, morphs: Morphs) -> Result<()> {
        let path = path.as_ref();
        let text = path.to_str().ok_or_else(|| Error::invalid(format!("{} is not UTF-8", path.display())))?;
        let c_path = c_string(text, "the path")?;
        let mut def = std::mem::MaybeUninit::<sys::ssc_export_def>::uninit();
        // Safety: ssc_export_def_init fills every field.
        let mut def = unsafe {
            sys::ssc_export_def_init(def.as_mut_ptr(), std::mem::size_of::<sys::ssc_export_def>());
            def.assume_init()
        };
        def.level = if level == ALL_LEVELS { u32::MAX } else { u32::try_from(level).map_err(|_| Error::invalid(format!("level {}", level)))? };
        match morphs {
            Morphs::Components(k) => {
                def.morphs = sys::SSC_MORPHS_COMPONENTS;
                def.morph_count = u32::try_from(k).map_err(|_| Error::invalid(format!("{} components", k)))?;
            }
            Morphs::Sliders => def.morphs = sys::SSC_MORPHS_SLIDERS,
        }
        check(unsafe { sys::ssc_body_export(self.raw.as_ptr(), c_path.as_ptr(), &def) })
    }

    /// A level of detail's posed vertices, its `vertex_count * 3`.
    pub fn level_vertices(&mut self, level: usize) -> Result<Vec<f32>> {
        let n = *self.counts.level_vertices.get(level).ok_or_else(|| Error::invalid(format!("level {} is out of range", level)))?;
        let mut out = vec![0f32; n * 3];
        check(unsafe { sys::ssc_body_get_level_vertices(self.raw.as_ptr(), level as u32, out.as_mut_ptr(), n as u32, 0) })?;
        Ok(out)
    }
}

/// A fitted pose: `joint_count` quaternions, the root translation and the scale.
#[derive(Clone, Debug, PartialEq)]
pub struct Pose {
    pub rotations: Vec<f32>,
    pub translation: [f32; 3],
    pub scale: f32,
}

/// Fits shape and pose to landmarks and scan points.
pub struct Fitter {
    raw: NonNull<sys::ssc_fitter>,
    counts: Counts,
}

// Safety: as Body: one thread at a time, which &mut self and !Sync give.
unsafe impl Send for Fitter {}

impl Drop for Fitter {
    fn drop(&mut self) {
        unsafe { sys::ssc_fitter_destroy(self.raw.as_ptr()) };
    }
}

unsafe extern "C" fn progress_trampoline(user: *mut c_void, iteration: u32, cost: f32) -> c_int {
    // Safety: user is the &mut dyn FnMut that solve_with_progress passed; a panic must not unwind
    // into C, so it cancels instead.
    let callback = &mut *(user as *mut &mut dyn FnMut(u32, f32) -> bool);
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| callback(iteration, cost))) {
        Ok(cancel) => cancel as c_int,
        Err(_) => 1,
    }
}

impl Fitter {
    /// The raw handle, for calls through [`sys`].
    pub fn as_ptr(&mut self) -> *mut sys::ssc_fitter {
        self.raw.as_ptr()
    }

    /// Landmarks of a frame by name, with positions (`names.len() * 3`, metres) and optional weights.
    pub fn add_landmarks_by_name<S: AsRef<str>>(&mut self, frame: u32, names: &[S], positions: &[f32], weights: Option<&[f32]>) -> Result<()> {
        count_of(positions, 3, names.len(), "positions")?;
        if let Some(w) = weights {
            count_of(w, 1, names.len(), "weights")?;
        }
        let owned = names.iter().map(|n| c_string(n.as_ref(), "a landmark name")).collect::<Result<Vec<_>>>()?;
        let pointers: Vec<*const c_char> = owned.iter().map(|n| n.as_ptr()).collect();
        check(unsafe {
            sys::ssc_fitter_add_landmarks_by_name(self.raw.as_ptr(), frame, pointers.as_ptr(), positions.as_ptr(),
                                                  weights.map_or(ptr::null(), |w| w.as_ptr()), u32_len(names.len(), "landmarks")?)
        })
    }

    /// Scan points of a frame (`count * 3`, metres), with normals when known.
    pub fn add_points(&mut self, frame: u32, points: &[f32], normals: Option<&[f32]>) -> Result<()> {
        if points.len() % 3 != 0 {
            return Err(Error::invalid(format!("points: {} values are not whole points", points.len())));
        }
        if let Some(n) = normals {
            count_of(n, 1, points.len(), "normals")?;
        }
        check(unsafe {
            sys::ssc_fitter_add_points(self.raw.as_ptr(), frame, points.as_ptr(), normals.map_or(ptr::null(), |n| n.as_ptr()),
                                       ptr::null(), u32_len(points.len() / 3, "points")?, 0)
        })
    }

    /// Solves; the report says how it went (non-convergence is a report field, not an error).
    pub fn solve(&mut self) -> Result<sys::ssc_fit_report> {
        self.solve_inner(None)
    }

    /// As [`Fitter::solve`], calling `progress(iteration, cost)` each iteration; returning true
    /// cancels (`SSC_ERROR_CANCELLED`).
    pub fn solve_with_progress(&mut self, mut progress: impl FnMut(u32, f32) -> bool) -> Result<sys::ssc_fit_report> {
        let mut callback: &mut dyn FnMut(u32, f32) -> bool = &mut progress;
        self.solve_inner(Some(&mut callback))
    }

    fn solve_inner(&mut self, callback: Option<&mut &mut dyn FnMut(u32, f32) -> bool>) -> Result<sys::ssc_fit_report> {
        // Safety: all-zero is a valid ssc_fit_report (plain numbers); struct_size says how much to fill.
        let mut report: sys::ssc_fit_report = unsafe { std::mem::zeroed() };
        report.struct_size = std::mem::size_of::<sys::ssc_fit_report>() as u32;
        let (function, user): (sys::ssc_progress_fn, *mut c_void) = match callback {
            Some(c) => (Some(progress_trampoline), c as *mut &mut dyn FnMut(u32, f32) -> bool as *mut c_void),
            None => (None, ptr::null_mut()),
        };
        check(unsafe { sys::ssc_fitter_solve(self.raw.as_ptr(), function, user, &mut report) })?;
        Ok(report)
    }

    /// The fitted shape coefficients.
    pub fn shape(&self) -> Result<Vec<f32>> {
        let mut out = vec![0f32; self.counts.shapes];
        check(unsafe { sys::ssc_fitter_get_shape(self.raw.as_ptr(), out.as_mut_ptr(), out.len() as u32) })?;
        Ok(out)
    }

    /// The fitted pose of a frame.
    pub fn pose(&self, frame: u32) -> Result<Pose> {
        let mut pose = Pose { rotations: vec![0f32; self.counts.joints * 4], translation: [0.0; 3], scale: 0.0 };
        check(unsafe {
            sys::ssc_fitter_get_pose(self.raw.as_ptr(), frame, pose.rotations.as_mut_ptr(), self.counts.joints as u32,
                                     pose.translation.as_mut_ptr(), &mut pose.scale)
        })?;
        Ok(pose)
    }

    /// The fitted body's vertices in a frame, `vertex_count * 3`.
    pub fn vertices(&self, frame: u32) -> Result<Vec<f32>> {
        let mut out = vec![0f32; self.counts.vertices * 3];
        check(unsafe { sys::ssc_fitter_get_vertices(self.raw.as_ptr(), frame, out.as_mut_ptr(), self.counts.vertices as u32, 0) })?;
        Ok(out)
    }
}
