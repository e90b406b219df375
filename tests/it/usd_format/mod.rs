//! USD BasisCurves stages (issue 20), a file per concern: a stage written by hand loads with the counts, bounds and
//! thicknesses derived by hand (`read`); `.hair` → `.usda` → `.hair` keeps every array, one groom as `.usda`,
//! `.tfx` and `.data` gives the same strands (`round_trip`); bad stages are refused naming the file, the prim and
//! the attribute, and malformed binary files in one line (`malformed`). The hand-written stage, the test USDZ
//! writer (the fuzz targets use both) and a file writer are here.

mod malformed;
mod read;
mod round_trip;

/// Z-up, centimetres, 12 time codes per second. `/Groom` translates by (10, 0, 0) after scaling by 2, so a local
/// point `p` is at `2p + (10, 0, 0)` in the stage, then `(x, y, z)` → `(x, z, −y)` (Z-up to Y-up) and × 0.01
/// (centimetres to metres). Widths scale by 2 × 0.01 = 0.02.
/// - `Linear`: linear, counts [3, 2], vertex widths, uniform colour (red, green).
/// - `Bezier`: nothing authored but counts and points (the schema's fallbacks: cubic bezier nonperiodic), one
///   curve of 4 control points, time-sampled at 0 and 2 (moved by +1 in x at 2), constant width 0.5.
/// - `Bspline`: cubic bspline, one curve of 5 control points (2 spans), varying widths [0.2, 0.4, 0.2], constant
///   opacity 0.5.
pub(crate) const HAND_STAGE: &str = r#"#usda 1.0
(
    upAxis = "Z"
    metersPerUnit = 0.01
    timeCodesPerSecond = 12
)

def Xform "Groom"
{
    double3 xformOp:translate = (10, 0, 0)
    float3 xformOp:scale = (2, 2, 2)
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:scale"]

    def BasisCurves "Linear"
    {
        uniform token type = "linear"
        int[] curveVertexCounts = [3, 2]
        point3f[] points = [(0, 0, 0), (0, 0, 1), (0, 0, 2), (1, 0, 0), (1, 0, 3)]
        float[] widths = [0.5, 0.25, 0.125, 1, 1] (
            interpolation = "vertex"
        )
        color3f[] primvars:displayColor = [(1, 0, 0), (0, 1, 0)] (
            interpolation = "uniform"
        )
    }

    def BasisCurves "Bezier"
    {
        int[] curveVertexCounts = [4]
        point3f[] points.timeSamples = {
            0: [(0, 0, 0), (0, 8, 4), (0, 8, 8), (0, 0, 12)],
            2: [(1, 0, 0), (1, 8, 4), (1, 8, 8), (1, 0, 12)],
        }
        float[] widths = [0.5] (
            interpolation = "constant"
        )
    }

    def BasisCurves "Bspline"
    {
        uniform token type = "cubic"
        uniform token basis = "bspline"
        int[] curveVertexCounts = [5]
        point3f[] points = [(0, 0, 0), (6, 0, 0), (12, 6, 0), (18, 0, 0), (24, 0, 0)]
        float[] widths = [0.2, 0.4, 0.2] (
            interpolation = "varying"
        )
        float[] primvars:displayOpacity = [0.5] (
            interpolation = "constant"
        )
    }
}
"#;

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// CRC-32 (IEEE), bitwise: enough for the small archives these tests write.
fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A `.usdz`: one stored (uncompressed) zip entry whose data starts on a 64-byte boundary, as USDZ requires.
pub(crate) fn usdz_of(name: &str, data: &[u8]) -> Vec<u8> {
    let crc = crc32(data);
    let size = u32::try_from(data.len()).unwrap();
    let name_len = u16::try_from(name.len()).unwrap();
    let mut extra = (64 - (30 + name.len()) % 64) % 64;
    if extra > 0 && extra < 4 {
        extra += 64;
    }
    let mut z = Vec::new();
    z.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
    z.extend_from_slice(&[20, 0, 0, 0, 0, 0, 0, 0, 0, 0]); // version, flags, method stored, time, date
    z.extend_from_slice(&crc.to_le_bytes());
    z.extend_from_slice(&size.to_le_bytes());
    z.extend_from_slice(&size.to_le_bytes());
    z.extend_from_slice(&name_len.to_le_bytes());
    z.extend_from_slice(&u16::try_from(extra).unwrap().to_le_bytes());
    z.extend_from_slice(name.as_bytes());
    if extra > 0 {
        // An unknown extra field (id 0x1986, as Pixar's writer uses) padding the data to 64 bytes.
        z.extend_from_slice(&0x1986u16.to_le_bytes());
        z.extend_from_slice(&u16::try_from(extra - 4).unwrap().to_le_bytes());
        z.resize(z.len() + extra - 4, 0);
    }
    assert_eq!(z.len() % 64, 0);
    z.extend_from_slice(data);
    let central = z.len();
    z.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
    z.extend_from_slice(&[20, 0, 20, 0, 0, 0, 0, 0, 0, 0, 0, 0]); // made by, needed, flags, method, time, date
    z.extend_from_slice(&crc.to_le_bytes());
    z.extend_from_slice(&size.to_le_bytes());
    z.extend_from_slice(&size.to_le_bytes());
    z.extend_from_slice(&name_len.to_le_bytes());
    z.extend_from_slice(&[0; 12]); // extra, comment, disk, internal and external attributes
    z.extend_from_slice(&0u32.to_le_bytes()); // local header offset
    z.extend_from_slice(name.as_bytes());
    let central_len = u32::try_from(z.len() - central).unwrap();
    z.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
    z.extend_from_slice(&[0, 0, 0, 0, 1, 0, 1, 0]);
    z.extend_from_slice(&central_len.to_le_bytes());
    z.extend_from_slice(&u32::try_from(central).unwrap().to_le_bytes());
    z.extend_from_slice(&[0, 0]);
    z
}
