//! [`GcAssembly`]: the document object kind of this module, an assembly of
//! GC parts, each with an optional parent link (§3.3's assembly graph,
//! child -> parent). Parents precede their children, so the graph is a
//! forest by construction. This session creates single-part assemblies;
//! the assembly module adds children, copies and symmetry on top.

use serde::{Deserialize, Serialize};

use super::{mesh_gc, Gc, GcError};
use crate::mesh::TriMesh;

/// One part of an assembly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GcPart {
    /// The part's generalized cylinder.
    pub gc: Gc,
    /// Index of the parent part (smaller than this part's index), or
    /// `None` for a root.
    pub parent: Option<usize>,
    /// Where a child sits on its parent's surface (see
    /// [`crate::assembly`]); `None` for roots.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attach: Option<super::Attachment>,
}

/// An assembly of generalized cylinders.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GcAssembly {
    /// Parts; a part's parent comes before it.
    pub parts: Vec<GcPart>,
    /// The relations recorded between the parts as they were added (see
    /// [`crate::assembly::RecordedRelations`]); `None` in assemblies saved
    /// before relations were recorded, which get them detected once.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relations: Option<super::RecordedRelations>,
}

impl GcAssembly {
    /// A one-part assembly.
    pub fn single(gc: Gc) -> Self {
        Self {
            parts: vec![GcPart {
                gc,
                parent: None,
                attach: None,
            }],
            relations: None,
        }
    }

    /// Checks the parent links.
    pub fn validate(&self) -> Result<(), GcError> {
        for (i, p) in self.parts.iter().enumerate() {
            if let Some(par) = p.parent {
                if par >= i {
                    return Err(GcError::BadPart {
                        index: par,
                        count: i,
                    });
                }
            }
        }
        Ok(())
    }

    /// The part `index`, mutably.
    pub fn part_mut(&mut self, index: usize) -> Result<&mut GcPart, GcError> {
        let count = self.parts.len();
        self.parts
            .get_mut(index)
            .ok_or(GcError::BadPart { index, count })
    }

    /// Every part meshed and appended (not a boolean union: parts overlap
    /// where they attach; the union is the assembly module's job).
    pub fn evaluate(&self) -> Result<TriMesh, GcError> {
        self.validate()?;
        let mut out = TriMesh::default();
        for p in &self.parts {
            out.append(&mesh_gc(&p.gc)?);
        }
        Ok(out)
    }
}
