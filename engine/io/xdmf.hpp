// XDMF sidecar of a result file: lets ParaView (and VisIt) open wiredem's result.h5.
//
// write_xdmf reads an existing result.h5 (layout: docs/results.md) and writes an
// XDMF 3 XML file that describes its arrays as ParaView-ready grids. The XML points
// into the HDF5 file by a path relative to the XDMF file ("result.h5:/specimen/…"),
// so the pair can be moved together; it only names datasets that exist, with their
// stored dimensions and number type.
//
// The Domain holds:
//   * "specimen": a spatial collection of the prepared specimen;
//   * one temporal collection per test ("sigma3_20000", …, by ascending pressure)
//     whose steps are the test's snapshots, Time = the snapshot's requested axial
//     strain (the same list in every test; the measured strain, then the snapshot
//     index, when it does not increase strictly); each step is a spatial collection
//     with the measured strain and the time in Information elements.
// Each spatial collection holds, when the file has the data:
//   * "grains": Polyvertex, one vertex cell per grain; point attributes radius_m and
//     (snapshots) velocity_m_per_s, for Point Gaussian or Glyph (scale by radius);
//   * "wire": Polyline of W − 1 two-node cells, one per segment; cell attribute
//     segment_strain (snapshots);
//   * "membrane": Triangle surface (the specimen takes the triangles of the first
//     snapshot with the same node count; without one, the nodes as Polyvertex);
//   * "contacts" (snapshots): the force network, one two-node Polyline cell per
//     contact pair between the bodies' centres; cell attributes normal_force_n and
//     force_n (on the first body; its magnitude is |F|).
// Arrays the result file does not hold are written inline in the XML
// (Format="XML"): the vertex lists 0 … n−1 (ParaView makes no cells without them),
// the wire's segment node pairs, and the contacts' end points (a pair's bodies can
// sit in two different position datasets, and ParaView's XDMF 3 reader does not
// evaluate the JOIN function or hyperslabs that could combine them). Everything
// else, including every attribute, is a reference into the HDF5 file.
//
// Errors: throws Hdf5Error when the result file cannot be read, std::runtime_error
// when the XDMF file cannot be written (it is written under a ".tmp" name, then
// renamed, so a failure leaves no half-written sidecar). Not thread-safe with
// respect to other users of the same result file (see hdf5.hpp).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace wiredem::engine::io {

/// What write_xdmf described.
struct XdmfSummary {
    bool specimen = false;      ///< whether the file has a /specimen group (described as "specimen")
    std::size_t tests = 0;      ///< temporal collections (one per /tests group with snapshots)
    std::size_t snapshots = 0;  ///< time steps over all tests
    std::size_t grids = 0;      ///< uniform grids (grains, wire, membrane, contacts) in total
};

/// The XDMF text describing `h5_path`, whose HDF5 references name the file as
/// `h5_reference` (a path relative to where the XDMF file will be, e.g. "result.h5").
/// @throws Hdf5Error when the result file cannot be read
[[nodiscard]] std::string xdmf_text(
    const std::filesystem::path& h5_path, const std::string& h5_reference, XdmfSummary* summary = nullptr);

/// Writes the XDMF sidecar of `h5_path` to `xdmf_path` (default: the same name with
/// the extension .xdmf, next to it). References name the HDF5 file relative to the
/// XDMF file's directory.
/// @throws Hdf5Error when the result file cannot be read, std::runtime_error when the
///         sidecar cannot be written
XdmfSummary write_xdmf(const std::filesystem::path& h5_path, std::filesystem::path xdmf_path = {});

} // namespace wiredem::engine::io
