//! Mode `ATTRIBUTES`: elements in blocks, each byte of the element stored as
//! zigzag deltas from the same byte of the previous element, in groups of
//! 16 coded with 0, 2, 4 or 8 bits a delta (the small codes with a sentinel
//! for deltas that do not fit, stored as whole bytes after the group).

/// The stream's first byte.
const HEADER: u8 = 0xa0;
/// Elements of a group.
const GROUP: usize = 16;
/// The tail holds the first baseline element, padded to at least this.
const TAIL: usize = 32;

/// Decodes `count` elements of `stride` bytes.
pub(super) fn decode(data: &[u8], count: usize, stride: usize) -> Result<Vec<u8>, String> {
    if stride == 0 || stride > 256 || !stride.is_multiple_of(4) {
        return Err(format!(
            "byteStride {stride} must be a multiple of 4 up to 256"
        ));
    }
    let tail = TAIL.max(stride);
    if data.len() < 1 + tail {
        return Err(format!("{} bytes are too few for a stream", data.len()));
    }
    if data[0] != HEADER {
        return Err(format!(
            "the stream starts with {:#04x}, not {HEADER:#04x} (an unknown version)",
            data[0]
        ));
    }
    let end = data.len() - tail;
    let mut last: Vec<u8> = data[data.len() - stride..].to_vec();
    let block = ((8192 / stride) & !(GROUP - 1)).min(256);
    let mut out = vec![0u8; count * stride];
    let mut at = 1;
    let mut deltas = vec![0u8; block.div_ceil(GROUP) * GROUP];
    let mut first = 0;
    while first < count {
        let n = block.min(count - first);
        let groups = n.div_ceil(GROUP);
        for byte in 0..stride {
            read_deltas(data, &mut at, end, groups, &mut deltas)?;
            let mut value = last[byte];
            for (i, &d) in deltas[..n].iter().enumerate() {
                value = value.wrapping_add(unzigzag(d));
                out[(first + i) * stride + byte] = value;
            }
            last[byte] = value;
        }
        first += n;
    }
    if at != end {
        return Err(format!(
            "{} bytes left over before the tail (the stream does not match count {count})",
            end - at
        ));
    }
    Ok(out)
}

fn unzigzag(v: u8) -> u8 {
    if v & 1 == 0 {
        v >> 1
    } else {
        !(v >> 1)
    }
}

/// The deltas of one byte position over `groups` groups: the header bits,
/// then each group's codes.
fn read_deltas(
    data: &[u8],
    at: &mut usize,
    end: usize,
    groups: usize,
    deltas: &mut [u8],
) -> Result<(), String> {
    let header_len = groups.div_ceil(4);
    let short = || "the stream ends inside a block".to_string();
    let header = data
        .get(*at..*at + header_len)
        .filter(|_| *at + header_len <= end)
        .ok_or_else(short)?;
    let header: Vec<u8> = header.to_vec();
    *at += header_len;
    for g in 0..groups {
        let bits = (header[g / 4] >> ((g % 4) * 2)) & 3;
        let group = &mut deltas[g * GROUP..(g + 1) * GROUP];
        match bits {
            0 => group.fill(0),
            3 => {
                let raw = data
                    .get(*at..*at + GROUP)
                    .filter(|_| *at + GROUP <= end)
                    .ok_or_else(short)?;
                group.copy_from_slice(raw);
                *at += GROUP;
            }
            _ => {
                let width = if bits == 1 { 2 } else { 4 };
                let packed_len = GROUP * width / 8;
                let packed = data
                    .get(*at..*at + packed_len)
                    .filter(|_| *at + packed_len <= end)
                    .ok_or_else(short)?
                    .to_vec();
                *at += packed_len;
                let per_byte = 8 / width;
                let sentinel = (1u8 << width) - 1;
                for (i, d) in group.iter_mut().enumerate() {
                    // Most significant bits first.
                    let shift = 8 - width * (i % per_byte + 1);
                    let code = (packed[i / per_byte] >> shift) & sentinel;
                    *d = if code == sentinel {
                        let extra = *data.get(*at).filter(|_| *at < end).ok_or_else(short)?;
                        *at += 1;
                        extra
                    } else {
                        code
                    };
                }
            }
        }
    }
    Ok(())
}
