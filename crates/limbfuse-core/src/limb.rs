//! Names of the limb's segments and joints (SPEC section 1).

/// A body segment of one leg, proximal to distal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Segment {
    /// Trunk (or pelvis, used as the body segment).
    Trunk = 0,
    /// Thigh.
    Thigh = 1,
    /// Shank.
    Shank = 2,
    /// Foot.
    Foot = 3,
}

impl Segment {
    /// All segments, proximal to distal.
    pub const ALL: [Segment; 4] = [
        Segment::Trunk,
        Segment::Thigh,
        Segment::Shank,
        Segment::Foot,
    ];

    /// The column-name stem of this segment (`trunk`, `thigh`, `shank`, `foot`).
    pub const fn name(self) -> &'static str {
        match self {
            Segment::Trunk => "trunk",
            Segment::Thigh => "thigh",
            Segment::Shank => "shank",
            Segment::Foot => "foot",
        }
    }

    /// Index 0..4 of this segment.
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// Which leg a single-leg trial records (SPEC section 2, `# leg:`). The
/// aligned frame is the same for both legs (SPEC section 1: z to the
/// subject's right); a left leg's motion is the mirror image of a right
/// leg's across the sagittal plane.
///
/// The same concept as [`Side`] (issue 14's alignment and issue 19's
/// two-leg recordings met here): one type under two names.
pub type Leg = Side;

/// A joint between two adjacent segments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Joint {
    /// Hip: `theta_trunk - theta_thigh`.
    Hip = 0,
    /// Knee: `theta_thigh - theta_shank`.
    Knee = 1,
    /// Ankle: `theta_shank - theta_foot`.
    Ankle = 2,
}

impl Joint {
    /// All joints, proximal to distal.
    pub const ALL: [Joint; 3] = [Joint::Hip, Joint::Knee, Joint::Ankle];

    /// The column-name stem of this joint (`hip`, `knee`, `ankle`).
    pub const fn name(self) -> &'static str {
        match self {
            Joint::Hip => "hip",
            Joint::Knee => "knee",
            Joint::Ankle => "ankle",
        }
    }

    /// Index 0..3 of this joint.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The proximal and distal segment of this joint.
    pub const fn segments(self) -> (Segment, Segment) {
        match self {
            Joint::Hip => (Segment::Trunk, Segment::Thigh),
            Joint::Knee => (Segment::Thigh, Segment::Shank),
            Joint::Ankle => (Segment::Shank, Segment::Foot),
        }
    }

    /// Joint angle from the absolute angles of its two segments (SPEC section 1).
    pub fn from_segments(self, segments: &[f64; 4]) -> f64 {
        let (p, d) = self.segments();
        segments[p.index()] - segments[d.index()]
    }
}

/// A body side (two-leg recordings: SPEC section 2's `# leg:` and `_left` /
/// `_right` column names; `contact_left` / `contact_right`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum Side {
    /// Left.
    Left = 0,
    /// Right (the single-leg names' default, SPEC section 2).
    #[default]
    Right = 1,
}

impl Side {
    /// Both sides, left first (the order of [`crate::Estimate::contact`]).
    pub const BOTH: [Side; 2] = [Side::Left, Side::Right];

    /// `left` or `right`.
    pub const fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }

    /// Index 0 (left) or 1 (right).
    pub const fn index(self) -> usize {
        self as usize
    }

    /// +1 for the right leg, -1 for the left: the sign of the leg's lateral
    /// (z) side.
    pub const fn lateral_sign(self) -> f64 {
        match self {
            Side::Right => 1.0,
            Side::Left => -1.0,
        }
    }

    /// The other side.
    pub const fn other(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }

    /// Parses `left` / `right` (case-insensitive, surrounding blanks ignored).
    pub fn parse(text: &str) -> Option<Side> {
        let t = text.trim();
        if t.eq_ignore_ascii_case("left") {
            Some(Side::Left)
        } else if t.eq_ignore_ascii_case("right") {
            Some(Side::Right)
        } else {
            None
        }
    }
}
