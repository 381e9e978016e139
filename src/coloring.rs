//! Two-step mesh coloring for race-free parallel Gauss-Seidel (docs/algorithm.md §5).
//!
//! The paper's step 1 lists, for each element, the elements that share no particle with it; step
//! 2 builds groups from those lists so that no two elements of a group share a particle. The lists
//! cost O(n²) memory, so here step 1 builds the particle → element incidence ([`Incidence`], CSR):
//! an element's neighbours are the elements incident to its particles and its non-adjacent list is
//! their complement. Step 2 colors greedily (first fit) with a 64-bit color mask per particle and
//! per layer of 64 colors, then a balancing sweep moves elements from groups larger than
//! `⌈n / colors⌉` to smaller groups where no particle conflicts. Cost: O(n · N) for the greedy
//! pass, O(n · N · colors) at worst for the balancing sweep; memory O(particles · layers).
//!
//! The color order is the one policy of the solver: groups run in increasing color index, and a
//! group's elements in increasing original index ([`Coloring::order`]).

use std::ops::Range;

/// Step 1: which elements touch each particle (compressed rows).
#[derive(Clone, Debug, Default)]
pub struct Incidence {
    /// `offsets[p]..offsets[p + 1]` indexes `elements` for particle `p`.
    pub offsets: Vec<u32>,
    /// Element indices, grouped by particle.
    pub elements: Vec<u32>,
}

impl Incidence {
    /// Builds the incidence of `elements` over `n_particles` particles.
    pub fn new<const N: usize>(n_particles: usize, elements: &[[u32; N]]) -> Self {
        let mut offsets = vec![0u32; n_particles + 1];
        for e in elements {
            for &p in e {
                offsets[p as usize + 1] += 1;
            }
        }
        for i in 0..n_particles {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut list = vec![0u32; offsets[n_particles] as usize];
        for (j, e) in elements.iter().enumerate() {
            for &p in e {
                list[fill[p as usize] as usize] = j as u32;
                fill[p as usize] += 1;
            }
        }
        Incidence { offsets, elements: list }
    }

    /// Number of elements touching particle `p`.
    pub fn degree(&self, p: usize) -> u32 {
        self.offsets[p + 1] - self.offsets[p]
    }

    /// Elements touching particle `p`.
    pub fn of(&self, p: usize) -> &[u32] {
        &self.elements[self.offsets[p] as usize..self.offsets[p + 1] as usize]
    }
}

/// A partition of elements into color groups.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Coloring {
    /// Color of each element.
    pub color_of: Vec<u32>,
    /// Number of colors (groups).
    pub num_colors: u32,
}

/// Color count and group-size balance of a [`Coloring`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct ColorStats {
    /// Number of groups.
    pub colors: u32,
    /// Smallest group size.
    pub min_group: u32,
    /// Largest group size.
    pub max_group: u32,
}

impl std::fmt::Display for ColorStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} colors, group sizes {}..{}", self.colors, self.min_group, self.max_group)
    }
}

/// Step 2: colors `elements` (each a list of `N` particle indices below `n_particles`) so that no
/// two elements of a color share a particle, with balanced group sizes.
pub fn color<const N: usize>(n_particles: usize, elements: &[[u32; N]]) -> Coloring {
    let mut masks: Vec<Vec<u64>> = Vec::new();
    let mut color_of = vec![0u32; elements.len()];
    let mut sizes: Vec<u32> = Vec::new();
    for (j, e) in elements.iter().enumerate() {
        let mut layer = 0;
        let c = loop {
            if layer == masks.len() {
                masks.push(vec![0u64; n_particles]);
            }
            let used = e.iter().fold(0u64, |m, &p| m | masks[layer][p as usize]);
            if used != u64::MAX {
                break layer as u32 * 64 + (!used).trailing_zeros();
            }
            layer += 1;
        };
        set(&mut masks, e, c, true);
        color_of[j] = c;
        if sizes.len() <= c as usize {
            sizes.resize(c as usize + 1, 0);
        }
        sizes[c as usize] += 1;
    }
    balance(elements, &mut masks, &mut color_of, &mut sizes);
    // Drop colors the balancing emptied, keeping the order of the rest.
    let mut remap = vec![u32::MAX; sizes.len()];
    let mut next = 0;
    for (c, &s) in sizes.iter().enumerate() {
        if s > 0 {
            remap[c] = next;
            next += 1;
        }
    }
    for c in &mut color_of {
        *c = remap[*c as usize];
    }
    Coloring { color_of, num_colors: next }
}

fn set<const N: usize>(masks: &mut [Vec<u64>], e: &[u32; N], c: u32, on: bool) {
    let (layer, bit) = ((c / 64) as usize, 1u64 << (c % 64));
    for &p in e {
        let m = &mut masks[layer][p as usize];
        if on {
            *m |= bit;
        } else {
            *m &= !bit;
        }
    }
}

/// One sweep moving elements out of over-full groups into groups below the mean size.
fn balance<const N: usize>(elements: &[[u32; N]], masks: &mut [Vec<u64>], color_of: &mut [u32], sizes: &mut [u32]) {
    let k = sizes.len() as u32;
    if k < 2 {
        return;
    }
    let target = (elements.len() as u32).div_ceil(k);
    for (j, e) in elements.iter().enumerate() {
        let c = color_of[j];
        if sizes[c as usize] <= target {
            continue;
        }
        let free = (0..k).find(|&c2| {
            sizes[c2 as usize] < target && {
                let (layer, bit) = ((c2 / 64) as usize, 1u64 << (c2 % 64));
                e.iter().all(|&p| masks[layer][p as usize] & bit == 0)
            }
        });
        if let Some(c2) = free {
            set(masks, e, c, false);
            set(masks, e, c2, true);
            color_of[j] = c2;
            sizes[c as usize] -= 1;
            sizes[c2 as usize] += 1;
        }
    }
}

impl Coloring {
    /// Group sizes and count.
    pub fn stats(&self) -> ColorStats {
        let mut sizes = vec![0u32; self.num_colors as usize];
        for &c in &self.color_of {
            sizes[c as usize] += 1;
        }
        ColorStats {
            colors: self.num_colors,
            min_group: sizes.iter().copied().min().unwrap_or(0),
            max_group: sizes.iter().copied().max().unwrap_or(0),
        }
    }

    /// The solver's order: element indices sorted by color (stable, so increasing index within a
    /// color), and the range of that order each color occupies.
    pub fn order(&self) -> (Vec<u32>, Vec<Range<u32>>) {
        let mut counts = vec![0u32; self.num_colors as usize + 1];
        for &c in &self.color_of {
            counts[c as usize + 1] += 1;
        }
        for c in 0..self.num_colors as usize {
            counts[c + 1] += counts[c];
        }
        let ranges = (0..self.num_colors as usize).map(|c| counts[c]..counts[c + 1]).collect();
        let mut fill = counts;
        let mut perm = vec![0u32; self.color_of.len()];
        for (j, &c) in self.color_of.iter().enumerate() {
            perm[fill[c as usize] as usize] = j as u32;
            fill[c as usize] += 1;
        }
        (perm, ranges)
    }

    /// Checks the partition: every element has a color below `num_colors` and no two elements of
    /// a color share a particle. Returns a description of the first violation.
    pub fn validate<const N: usize>(&self, n_particles: usize, elements: &[[u32; N]]) -> Result<(), String> {
        if self.color_of.len() != elements.len() {
            return Err(format!("{} colors for {} elements", self.color_of.len(), elements.len()));
        }
        let mut owner = vec![u32::MAX; n_particles];
        let mut seen_color = vec![u32::MAX; n_particles];
        for c in 0..self.num_colors {
            for (j, e) in elements.iter().enumerate() {
                if self.color_of[j] != c {
                    continue;
                }
                for &p in e {
                    if seen_color[p as usize] == c {
                        return Err(format!("color {c}: elements {} and {j} share particle {p}", owner[p as usize]));
                    }
                    seen_color[p as usize] = c;
                    owner[p as usize] = j as u32;
                }
            }
        }
        if let Some(j) = self.color_of.iter().position(|&c| c >= self.num_colors) {
            return Err(format!("element {j} has color {} of {}", self.color_of[j], self.num_colors));
        }
        Ok(())
    }
}
