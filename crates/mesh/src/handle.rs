//! Typed indices into the mesh's property arrays.
//!
//! Every element of a [`Mesh`](crate::Mesh) is addressed by a 32-bit handle; properties are plain
//! `Vec`s indexed by `handle.idx()`. The value `u32::MAX` is reserved as "none".

macro_rules! handle {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
        #[repr(transparent)]
        pub struct $name(pub u32);

        impl $name {
            /// The reserved "no element" value.
            pub const NONE: Self = Self(u32::MAX);
            /// The handle as an array index.
            #[inline]
            pub const fn idx(self) -> usize {
                self.0 as usize
            }
            /// `true` unless this is [`Self::NONE`].
            #[inline]
            pub const fn is_some(self) -> bool {
                self.0 != u32::MAX
            }
            /// `Some(self)` unless this is [`Self::NONE`].
            #[inline]
            pub const fn get(self) -> Option<Self> {
                if self.is_some() { Some(self) } else { None }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{}", self.0)
            }
        }
    };
}

handle!(
    /// A vertex.
    VertexId
);
handle!(
    /// A half-edge: edge `e` owns half-edges `2e` and `2e + 1`, which are each other's twins.
    HalfedgeId
);
handle!(
    /// An undirected edge.
    EdgeId
);
handle!(
    /// A face (polygon with three or more vertices).
    FaceId
);

impl HalfedgeId {
    /// The opposite half-edge of the same edge.
    #[inline]
    pub const fn twin(self) -> Self {
        Self(self.0 ^ 1)
    }
    /// The edge this half-edge belongs to.
    #[inline]
    pub const fn edge(self) -> EdgeId {
        EdgeId(self.0 >> 1)
    }
}

impl EdgeId {
    /// The half-edge of this edge with index `2e + side` (`side` is 0 or 1).
    #[inline]
    pub const fn halfedge(self, side: u32) -> HalfedgeId {
        HalfedgeId(self.0 * 2 + (side & 1))
    }
}
