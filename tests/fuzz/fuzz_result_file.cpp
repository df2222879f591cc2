// The result file reader behind `wiredem export-xdmf RESULT.h5` (engine/io/xdmf,
// client/export_command.cpp): a result file the client reads may come from
// anywhere. Byte-level mutations of an HDF5 file mostly break its checksums
// and compressed chunks, so the input describes a result file instead: which
// groups and datasets of the documented layout (docs/results.md) exist, their
// sizes, element types and contents, above all the indices that point into
// other datasets (contact bodies, membrane triangles). The file is written
// with the engine's HDF5 layer to a temporary path and read back with
// engine::io::xdmf_text: it must give XML or throw Hdf5Error, never crash.
#include "fuzz_check.hpp"

#include "io/hdf5.hpp"
#include "io/xdmf.hpp"

#include <fuzzer/FuzzedDataProvider.h>

#include <unistd.h>

#include <string>
#include <vector>

using namespace wiredem;
namespace io = engine::io;

namespace {

std::vector<engine::Vec3> points(FuzzedDataProvider& in, std::size_t n)
{
    std::vector<engine::Vec3> p;
    for (std::size_t i = 0; i < n; ++i) p.emplace_back(in.ConsumeFloatingPoint<double>(), 1e-3 * static_cast<double>(i), 0.0);
    return p;
}

/// Indices into other datasets: small ones mostly, any 32- or 64-bit value sometimes.
void write_indices(FuzzedDataProvider& in, io::Group& g, const char* name, std::size_t rows, std::size_t columns)
{
    const bool wide = in.ConsumeBool();
    std::vector<std::uint32_t> narrow;
    std::vector<std::int64_t> any;
    for (std::size_t i = 0; i < rows * columns; ++i) {
        const std::int64_t v = in.ConsumeBool() ? in.ConsumeIntegralInRange<std::int64_t>(-1, 9)
                                                : in.ConsumeIntegral<std::int64_t>();
        narrow.push_back(static_cast<std::uint32_t>(v));
        any.push_back(v);
    }
    if (wide) g.write_dataset(name, std::span<const std::int64_t>(any), columns);
    else g.write_dataset(name, std::span<const std::uint32_t>(narrow), columns);
}

/// The bodies of a specimen or a snapshot, each dataset present or not.
void write_bodies(FuzzedDataProvider& in, io::Group& g, bool snapshot)
{
    const std::size_t grains = in.ConsumeIntegralInRange<std::size_t>(0, 6);
    const std::size_t wire = in.ConsumeIntegralInRange<std::size_t>(0, 5);
    const std::size_t membrane = in.ConsumeIntegralInRange<std::size_t>(0, 6);
    if (in.ConsumeBool()) g.write_dataset("grain_position_m", points(in, grains));
    if (in.ConsumeBool()) g.write_dataset("grain_radius_m", std::vector<double>(in.ConsumeBool() ? grains : grains + 1, 1e-3));
    if (in.ConsumeBool()) g.write_dataset("wire_node_position_m", points(in, wire));
    if (in.ConsumeBool()) g.write_dataset("membrane_node_position_m", points(in, membrane));
    if (in.ConsumeBool()) write_indices(in, g, "membrane_triangles", in.ConsumeIntegralInRange<std::size_t>(0, 4), in.ConsumeBool() ? 3 : 2);
    if (!snapshot) return;
    if (in.ConsumeBool()) g.write_dataset("grain_velocity_m_per_s", points(in, grains));
    if (in.ConsumeBool())
        g.write_dataset("wire_segment_strain", std::vector<double>(in.ConsumeIntegralInRange<std::size_t>(0, 6), 1e-3));
    const std::size_t contacts = in.ConsumeIntegralInRange<std::size_t>(0, 4);
    if (in.ConsumeBool()) write_indices(in, g, "contact_bodies", contacts, in.ConsumeBool() ? 4 : 3);
    if (in.ConsumeBool()) g.write_dataset("contact_force_n", points(in, contacts));
    if (in.ConsumeBool()) g.write_dataset("contact_normal_force_n", std::vector<double>(contacts, 1.0));
}

void write_result(FuzzedDataProvider& in, const std::string& path)
{
    io::write_file_atomically(path, [&](io::Group& root) {
        if (in.ConsumeBool()) root.write_string_attribute("format", "wiredem-result-1");
        if (in.ConsumeBool()) {
            io::Group sp = root.create_group("specimen");
            write_bodies(in, sp, false);
        }
        const int tests = in.ConsumeIntegralInRange<int>(0, 3);
        for (int t = 0; t < tests; ++t) {
            io::Group tg = root.create_group("tests/sigma3_" + std::to_string(in.ConsumeIntegral<std::int32_t>()));
            if (in.ConsumeBool()) tg.write_double_attribute("confining_pressure_pa", in.ConsumeFloatingPoint<double>());
            const int snapshots = in.ConsumeIntegralInRange<int>(0, 3);
            for (int s = 0; s < snapshots; ++s) {
                io::Group sg = tg.create_group("snapshots/snapshot_" + std::to_string(in.ConsumeIntegralInRange<int>(-1, 12)));
                if (in.ConsumeBool()) sg.write_double_attribute("requested_axial_strain", in.ConsumeFloatingPoint<double>());
                if (in.ConsumeBool()) sg.write_double_attribute("axial_strain", in.ConsumeFloatingPoint<double>());
                if (in.ConsumeBool()) sg.write_double_attribute("time_s", in.ConsumeFloatingPoint<double>());
                write_bodies(in, sg, true);
            }
        }
    });
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static const std::string path = "/tmp/wiredem-fuzz-result-" + std::to_string(::getpid()) + ".h5";
    FuzzedDataProvider in(data, size);
    bool written = true;
    try {
        write_result(in, path);
    } catch (const io::Hdf5Error&) {
        written = false;  // a layout the writer refuses (e.g. a group named twice): nothing to read
    }
    if (written) {
        try {
            io::XdmfSummary summary;
            const std::string xml = io::xdmf_text(path, "result.h5", &summary);
            FUZZ_CHECK(xml.find("<Xdmf") != std::string::npos, xml);
        } catch (const io::Hdf5Error&) {
            // a file it cannot read: the client says so (exit code local_io)
        }
    }
    ::unlink(path.c_str());
    return 0;
}
