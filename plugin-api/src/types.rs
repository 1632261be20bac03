//! Plain data of the calls made once per object or per beam: `#[repr(C)]`, `StableAbi`, in
//! double precision (the seed's `double`), so a beam means the same thing on both sides. The
//! render loop's per-sample data (single precision, wavelength lanes) is in [`crate::lanes`].

use abi_stable::StableAbi;
use serde::{Deserialize, Serialize};

/// How many wavelengths a path carries at once across the boundary (hero + rotations).
pub const LANES: usize = 4;

/// A point, direction or normal in the right-handed world frame (x right, y up, +z towards the
/// viewer), in scene units.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vec3 {
    /// x (right)
    pub x: f64,
    /// y (up)
    pub y: f64,
    /// z (towards the viewer)
    pub z: f64,
}

impl Vec3 {
    /// Build from components.
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }
    /// Dot product.
    pub fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Euclidean length.
    pub fn length(self) -> f64 {
        self.dot(self).sqrt()
    }
    /// This vector scaled to unit length (unchanged if it has zero length).
    pub fn normalized(self) -> Self {
        let l = self.length();
        if l > 0.0 {
            self * (1.0 / l)
        } else {
            self
        }
    }
    /// Cross product (right-handed).
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    /// True when every component is finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

impl std::ops::Add for Vec3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl std::ops::Sub for Vec3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl std::ops::Mul<f64> for Vec3 {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}
impl std::ops::Neg for Vec3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

/// One beam of light, the seed's unit of emission: where it starts, where it goes, its colour as
/// a wavelength and its power, and which source emitted it.
///
/// Radiometric meaning of `power`: a beam is one Monte Carlo sample of its source's emission. Its
/// `power` (W) is the source's whole radiant flux as estimated by this one sample: the emitted
/// spectral flux at `wavelength_nm` divided by the probability density of having drawn this
/// wavelength, origin and direction. Averaging `power` over a source's beams therefore converges
/// to its radiant flux, and a receiver that collects beams divides its sum by the source's
/// [`number_of_beams`](crate::LightSource) to get watts.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Beam {
    /// Start point (scene units).
    pub origin: Vec3,
    /// Unit direction of travel.
    pub direction: Vec3,
    /// Wavelength in nm.
    pub wavelength_nm: f64,
    /// Power in W, as defined above.
    pub power_w: f64,
    /// Id of the emitting source, assigned by the host when the source joins a scene
    /// (the seed's `parent` reference, as a number that survives the ABI).
    pub source_id: u64,
}

/// The uniform random numbers in `[0, 1)` a call may use. The host draws them, so objects hold no
/// random state: the same numbers give the same result, on any thread. Which entries a call reads
/// is documented per call; unused ones are ignored.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RandomSample {
    /// The numbers, each in `[0, 1)`.
    pub u: [f64; 8],
}

/// Whether a path carries radiance (from the camera) or importance (from a light). Non-symmetric
/// scattering (refraction, shading normals) differs between the two.
#[repr(u8)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Camera subpath: the path carries radiance towards the eye.
    Radiance,
    /// Light subpath: the path carries importance.
    Importance,
}

/// A set of capability bits; each object kind documents what its bits mean.
#[repr(transparent)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Flags(pub u32);

impl Flags {
    /// No bits.
    pub const NONE: Self = Self(0);
    /// True when every bit of `other` is set.
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }
    /// Union.
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }
}

impl std::ops::BitOr for Flags {
    type Output = Self;
    fn bitor(self, o: Self) -> Self {
        self.union(o)
    }
}

/// A wavelength interval in nm (arrays cannot be returned by value through `extern "C"`).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WavelengthRange {
    /// Shortest wavelength, nm.
    pub min_nm: f64,
    /// Longest wavelength, nm.
    pub max_nm: f64,
}

/// Tristimulus values (or colour-matching function values) X, Y, Z.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Xyz {
    /// X
    pub x: f64,
    /// Y (luminance-like)
    pub y: f64,
    /// Z
    pub z: f64,
}

/// The scene's extent, handed to a light once the scene is built
/// ([`LightSource::scene_bounds`](crate::LightSource::scene_bounds)): lights that cover the whole
/// scene (a distant sun, a sky) size themselves from it. Boxes are axis-aligned, in scene units.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SceneBounds {
    /// Smallest corner of the box around all geometry.
    pub min: Vec3,
    /// Largest corner of the box around all geometry.
    pub max: Vec3,
    /// Smallest corner of the box around all geometry and every camera position.
    pub view_min: Vec3,
    /// Largest corner of the box around all geometry and every camera position.
    pub view_max: Vec3,
}

impl SceneBounds {
    /// Centre and radius (scene units) of the sphere through the corners of the geometry box.
    pub fn bounding_sphere(&self) -> (Vec3, f64) {
        (
            (self.min + self.max) * 0.5,
            (self.max - self.min).length() * 0.5,
        )
    }
    /// Centre and radius (scene units) of the sphere through the corners of the view box.
    pub fn view_sphere(&self) -> (Vec3, f64) {
        (
            (self.view_min + self.view_max) * 0.5,
            (self.view_max - self.view_min).length() * 0.5,
        )
    }
    /// Centre and radius (scene units) of the sphere on which the host places an environment
    /// light: the view sphere's centre, 1.01 × its radius (at least 10⁻³). An environment
    /// declaring [`SPHERE_EMISSION`](crate::light_flags::SPHERE_EMISSION) starts its emitted
    /// rays on it.
    pub fn environment_sphere(&self) -> (Vec3, f64) {
        let (c, r) = self.view_sphere();
        (c, 1.01 * r.max(1e-3))
    }
}
