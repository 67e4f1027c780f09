/// \file site_rows.hpp
/// \brief Which input points (rows of a site table) each site of a triangulation holds, from
/// the BuildReport of its build: the one mapping from sites to rows that every product uses
/// (the cells' ids lists, the Delaunay layers' ids, the index file's attributes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"

namespace geovor {

/// The input points of each site, flat: site s holds inputs[begin[s] .. begin[s + 1]), the
/// point it was built from first, then the points merged into it in input order. (The point a
/// site was built from is not always its lowest: points merge into whichever of them the build
/// inserted first.)
struct SiteRows {
  std::vector<std::uint32_t> begin{0};  ///< size num_sites() + 1, ascending
  std::vector<std::uint32_t> inputs;    ///< indices of input points (rows of the SiteTable)

  std::size_t num_sites() const { return begin.size() - 1; }
  /// The input points of site s (empty for a site without any, e.g. removed). REQUIRES: s < num_sites().
  std::span<const std::uint32_t> of(SiteId s) const {
    return std::span<const std::uint32_t>(inputs).subspan(begin[s], begin[s + 1] - begin[s]);
  }
  /// The input point site s was built from, or kNoIndex if it holds none. REQUIRES: s < num_sites().
  std::uint32_t first(SiteId s) const { return begin[s] < begin[s + 1] ? inputs[begin[s]] : kNoIndex; }
};

/// The SiteRows of the `site_capacity` sites of a triangulation built with `report`
/// (SphericalDelaunay::site_capacity(); ids stay valid after relocation, which removes none).
/// An input whose site is kNoIndex or not below site_capacity is in no site; a Merge whose
/// input is out of range is ignored. O(inputs + sites).
SiteRows rows_of_sites(const BuildReport& report, std::size_t site_capacity);

}  // namespace geovor
