// HDF5 output layer: everything written is read back unchanged, numeric datasets are
// chunked and deflate-compressed, failures throw Hdf5Error naming file and object path
// without HDF5 printing to stderr, and h5dump (when installed) can read the file.
#include "io/atomic_file.hpp"
#include "io/hdf5.hpp"
#include "temp_dir.hpp"

#include <hdf5.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <fcntl.h>
#include <optional>
#include <stdexcept>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

using namespace wiredem::engine;
using namespace wiredem::engine::io;
using wiredem::engine::io::test::TempFile;

namespace {


/// Deflate level of a dataset's creation property list, or −1 when deflate is absent.
int deflate_level(const Dataset& ds)
{
    const hid_t dcpl = H5Dget_create_plist(ds.id());
    int level = -1;
    const int n = H5Pget_nfilters(dcpl);
    for (int i = 0; i < n; ++i) {
        unsigned flags = 0;
        std::size_t n_values = 1;
        unsigned values[1] = {0};
        char name[64];
        unsigned config = 0;
        const H5Z_filter_t filter = H5Pget_filter2(dcpl, static_cast<unsigned>(i), &flags, &n_values, values, sizeof name, name, &config);
        if (filter == H5Z_FILTER_DEFLATE) level = n_values > 0 ? static_cast<int>(values[0]) : 0;
    }
    H5Pclose(dcpl);
    return level;
}

std::vector<hsize_t> chunk_dims(const Dataset& ds)
{
    const hid_t dcpl = H5Dget_create_plist(ds.id());
    std::vector<hsize_t> dims(2, 0);
    const int rank = H5Pget_layout(dcpl) == H5D_CHUNKED ? H5Pget_chunk(dcpl, 2, dims.data()) : 0;
    H5Pclose(dcpl);
    dims.resize(static_cast<std::size_t>(std::max(rank, 0)));
    return dims;
}

} // namespace

TEST(Hdf5File, NestedGroupsAndAttributesRoundTrip)
{
    const TempFile tmp;
    {
        File f = File::create(tmp.path());
        Group root = f.root();
        root.write_string_attribute("engine", "wiredem");
        Group sample = root.create_group("tests/0/samples"); // intermediate groups on demand
        EXPECT_EQ(sample.path(), "/tests/0/samples");
        sample.write_string_attribute("units", "Pa");
        sample.write_double_attribute("confining_pressure_pa", 1.0e5);
        sample.write_int_attribute("sample_count", 1234567890123);
        root.create_group("tests/1");
        Group again = root.require_group("tests/0"); // exists: opened, not recreated
        EXPECT_EQ(again.path(), "/tests/0");
    }
    File f = File::open_read_only(tmp.path());
    Group root = f.root();
    EXPECT_TRUE(root.exists("tests/0/samples"));
    EXPECT_TRUE(root.exists("/tests/1"));
    EXPECT_FALSE(root.exists("tests/2/samples")); // a missing intermediate is not an error
    EXPECT_EQ(root.open_group("tests").child_names(), (std::vector<std::string>{"0", "1"}));
    EXPECT_EQ(root.read_string_attribute("engine"), "wiredem");
    const Group sample = root.open_group("tests/0/samples");
    EXPECT_TRUE(sample.has_attribute("units"));
    EXPECT_FALSE(sample.has_attribute("colour"));
    EXPECT_EQ(sample.read_string_attribute("units"), "Pa");
    EXPECT_EQ(sample.read_double_attribute("confining_pressure_pa"), 1.0e5);
    EXPECT_EQ(sample.read_int_attribute("sample_count"), 1234567890123);
}

/// Whether another open file description could take a lock on `path`
/// now (HDF5 locks the files it has open with flock, shared to read,
/// exclusive to write).
bool lockable(const std::filesystem::path& path, int operation)
{
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool ok = ::flock(fd, operation | LOCK_NB) == 0;
    ::close(fd);
    return ok;
}

/// HDF5's file locking, unless switched off for this process.
bool hdf5_locks_files()
{
    const char* v = std::getenv("HDF5_USE_FILE_LOCKING");
    return v == nullptr || (std::string(v) != "FALSE" && std::string(v) != "0");
}

// HDF5 closes a file only once the last object opened through it closes; until
// then it is neither fully written nor unlocked. close() refuses instead of
// pretending (a runner "closed" test_0.h5, renamed it, and the server's reader
// was refused "unable to lock file" until a group went out of scope).
TEST(Hdf5File, CloseRefusesWhileAnObjectIsOpenAndClosesOnceItIsNot)
{
    const TempFile tmp;
    File f = File::create(tmp.path());
    {
        Group g = f.root().create_group("tests");
        try {
            f.close();
            ADD_FAILURE() << "close() with an open group should throw";
        } catch (const Hdf5Error& e) {
            EXPECT_NE(std::string(e.what()).find("1 group(s), dataset(s) or attribute(s) opened through it are still open"),
                std::string::npos) << e.what();
        }
        g.write_int_attribute("still_writable", 1);  // the file stayed open
        if (hdf5_locks_files()) {
            EXPECT_FALSE(lockable(tmp.path(), LOCK_SH));
        }
    }
    f.close();
    EXPECT_EQ(f.id(), -1);
    EXPECT_TRUE(lockable(tmp.path(), LOCK_EX));
    const File r = File::open_read_only(tmp.path());
    EXPECT_EQ(r.root().open_group("tests").read_int_attribute("still_writable"), 1);
}

TEST(Hdf5File, WritingAtomicallyLeavesTheFileWholeOrAsItWas)
{
    const TempFile tmp;
    std::filesystem::path partial = tmp.path();
    partial += ".partial";
    write_file_atomically(tmp.path(), [](Group& root) { root.create_group("a").write_int_attribute("version", 1); });
    EXPECT_FALSE(std::filesystem::exists(partial));
    EXPECT_TRUE(lockable(tmp.path(), LOCK_EX));  // closed, not merely out of reach

    // A writer that fails half way: the partial file goes, the old file stays.
    EXPECT_THROW(write_file_atomically(tmp.path(),
                     [](Group& root) {
                         root.create_group("a").write_int_attribute("version", 2);
                         throw std::runtime_error("the writer failed");
                     }),
        std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(partial));
    // A writer that keeps an object open past its end cannot have the file renamed half closed.
    std::optional<Group> kept;
    EXPECT_THROW(write_file_atomically(tmp.path(), [&](Group& root) { kept = root.create_group("b"); }), Hdf5Error);
    kept.reset();
    EXPECT_FALSE(std::filesystem::exists(partial));
    const File r = File::open_read_only(tmp.path());
    EXPECT_EQ(r.root().open_group("a").read_int_attribute("version"), 1);
    EXPECT_FALSE(r.root().exists("b"));
}

// A full disk, injected (the partial file a symbolic link to /dev/full,
// where every write fails with ENOSPC): the writer throws one line naming the
// reason and the file, leaves no partial file and no HDF5 identifier open, and
// the library's exit handler (H5close, what H5_term_library runs at exit) goes
// through: with HDF5 writing to the disk itself, H5Dclose and H5Fclose failed
// and left the file open, and the exit handler crashed (SIGSEGV) closing it.
// In a child process, which the crash would kill.
TEST(Hdf5File, AFullDiskIsOneLineAndLeavesNoIdentifierOpen)
{
    const TempFile tmp;
    std::filesystem::path partial = tmp.path();
    partial += ".partial";
    std::filesystem::create_symlink("/dev/full", partial);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        int code = 0;
        try {
            write_file_atomically(tmp.path(), [](Group& root) {
                std::vector<double> values(200000);
                for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<double>(i * 2654435761u % 1000003);
                root.write_dataset("values", std::span<const double>(values));
            });
            code = 10;  // no error
        } catch (const WriteError& e) {
            if (std::string(e.what()) != "no space left on device writing " + tmp.path().string()) code = 11;
        } catch (const std::exception&) {
            code = 12;  // another error than a WriteError
        }
        if (std::filesystem::exists(std::filesystem::symlink_status(partial))) code = code ? code : 13;
        if (H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL) != 0) code = code ? code : 14;
        if (H5close() < 0) code = code ? code : 15;
        ::_exit(code);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    ASSERT_TRUE(WIFEXITED(status)) << "the child was killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 0) << "10: no error, 11: another message, 12: not a WriteError, 13: the partial "
                                         "file stayed, 14: an HDF5 identifier stayed open, 15: H5close failed";
}

TEST(Hdf5Attribute, RewritingReplacesTypeAndValue)
{
    const TempFile tmp;
    File f = File::create(tmp.path());
    Group root = f.root();
    root.write_string_attribute("x", "first");
    root.write_double_attribute("x", 2.5);
    EXPECT_EQ(root.read_double_attribute("x"), 2.5);
    root.write_string_attribute("x", "ünits: µm"); // UTF-8 survives
    EXPECT_EQ(root.read_string_attribute("x"), "ünits: µm");
    root.write_string_attribute("empty", "");
    EXPECT_EQ(root.read_string_attribute("empty"), "");
}

TEST(Hdf5Dataset, DoublesRoundTripInOneAndTwoDimensions)
{
    const TempFile tmp;
    std::vector<double> series(1000);
    for (std::size_t i = 0; i < series.size(); ++i) series[i] = 1e-3 * static_cast<double>(i) - 0.25;
    const std::vector<double> table = {1, 2, 3, 4, 5, 6, 7, 8}; // 4 × 2
    const std::vector<Vec3> positions = {Vec3(1e-3, -2e-3, 3e-3), Vec3(0.5, 0.25, -0.125)};
    {
        File f = File::create(tmp.path());
        Group run = f.root().create_group("run");
        Dataset q = run.write_dataset("deviatoric_stress_pa", series);
        q.write_string_attribute("units", "Pa");
        run.write_dataset("table", table, 2);
        run.write_dataset("positions_m", positions);
    }
    File f = File::open_read_only(tmp.path());
    const Group run = f.root().open_group("run");
    const Dataset q = run.open_dataset("deviatoric_stress_pa");
    EXPECT_EQ(q.shape(), (std::vector<std::size_t>{1000}));
    EXPECT_EQ(q.read_doubles(), series);
    EXPECT_EQ(q.read_string_attribute("units"), "Pa");
    const Dataset t = run.open_dataset("table");
    EXPECT_EQ(t.shape(), (std::vector<std::size_t>{4, 2}));
    EXPECT_EQ(t.read_doubles(), table);
    const Dataset p = f.root().open_dataset("/run/positions_m");
    EXPECT_EQ(p.shape(), (std::vector<std::size_t>{2, 3}));
    EXPECT_EQ(p.read_doubles(), (std::vector<double>{1e-3, -2e-3, 3e-3, 0.5, 0.25, -0.125}));
}

TEST(Hdf5Dataset, IntegersRoundTripWithTheirStoredTypes)
{
    const TempFile tmp;
    const std::vector<std::int32_t> i32 = {-5, 0, 2147483647};
    const std::vector<std::int64_t> i64 = {-(std::int64_t{1} << 62), 7};
    const std::vector<std::uint32_t> u32 = {0, 4294967295u, 1, 2, 3, 4}; // 3 × 2
    const std::vector<std::uint64_t> u64 = {std::uint64_t{1} << 40};
    File f = File::create(tmp.path());
    Group root = f.root();
    const Dataset a = root.write_dataset("i32", i32);
    const Dataset b = root.write_dataset("i64", i64);
    const Dataset c = root.write_dataset("u32", u32, 2);
    const Dataset d = root.write_dataset("u64", u64);
    EXPECT_EQ(a.read_int64s(), (std::vector<std::int64_t>{-5, 0, 2147483647}));
    EXPECT_EQ(b.read_int64s(), i64);
    EXPECT_EQ(c.shape(), (std::vector<std::size_t>{3, 2}));
    EXPECT_EQ(c.read_int64s(), (std::vector<std::int64_t>{0, 4294967295, 1, 2, 3, 4}));
    EXPECT_EQ(d.read_int64s(), (std::vector<std::int64_t>{std::int64_t{1} << 40}));

    // the stored types are the requested ones, not a common widening
    const hid_t type = H5Dget_type(a.id());
    EXPECT_EQ(H5Tget_size(type), 4u);
    EXPECT_EQ(H5Tget_sign(type), H5T_SGN_2);
    H5Tclose(type);
    const hid_t utype = H5Dget_type(c.id());
    EXPECT_EQ(H5Tget_sign(utype), H5T_SGN_NONE);
    H5Tclose(utype);
}

TEST(Hdf5Dataset, EmptyDatasetsRoundTripAndStayCompressed)
{
    const TempFile tmp;
    {
        File f = File::create(tmp.path());
        Group root = f.root();
        root.write_dataset("none", std::span<const double>{});
        root.write_dataset("no_rows", std::span<const double>{}, 3);
        root.write_dataset("no_ids", std::span<const std::uint32_t>{});
        root.write_dataset("no_vectors", std::span<const Vec3>{});
    }
    File f = File::open_read_only(tmp.path());
    const Group root = f.root();
    EXPECT_EQ(root.open_dataset("none").shape(), (std::vector<std::size_t>{0}));
    EXPECT_TRUE(root.open_dataset("none").read_doubles().empty());
    EXPECT_EQ(root.open_dataset("no_rows").shape(), (std::vector<std::size_t>{0, 3}));
    EXPECT_EQ(root.open_dataset("no_vectors").shape(), (std::vector<std::size_t>{0, 3}));
    EXPECT_TRUE(root.open_dataset("no_ids").read_int64s().empty());
    EXPECT_EQ(deflate_level(root.open_dataset("none")), 4);
    EXPECT_EQ(deflate_level(root.open_dataset("no_rows")), 4);
}

TEST(Hdf5Dataset, IsChunkedAndDeflateCompressedAtLevelFour)
{
    const TempFile tmp;
    File f = File::create(tmp.path());
    Group root = f.root();
    const std::vector<double> small = {1.0, 2.0, 3.0};
    const std::vector<double> large(100000, 0.5);
    const Dataset s = root.write_dataset("small", small);
    const Dataset l = root.write_dataset("large", large);
    const Dataset v = root.write_dataset("vectors", std::vector<double>(30000, 1.0), 3);
    EXPECT_EQ(deflate_level(s), 4);
    EXPECT_EQ(deflate_level(l), 4);
    EXPECT_EQ(deflate_level(v), 4);
    // chunks never exceed the data, and hold about 64 KiB of whole rows otherwise
    EXPECT_EQ(chunk_dims(s), (std::vector<hsize_t>{3}));
    EXPECT_EQ(chunk_dims(l), (std::vector<hsize_t>{8192}));
    EXPECT_EQ(chunk_dims(v), (std::vector<hsize_t>{2730, 3}));
    f.flush();
    // a constant series deflates to a small fraction of its 800 kB
    EXPECT_LT(H5Dget_storage_size(l.id()), large.size() * sizeof(double) / 20);
}

TEST(Hdf5StringDataset, StoresAJobSpecVerbatim)
{
    const TempFile tmp;
    const std::string spec = "{\n  \"name\": \"helix – R_a 12 mm\",\n  \"confining_pressure_pa\": [5e4, 1e5],\n"
                             "  \"note\": \"quotes \\\" and tabs\\t\"\n}\n";
    {
        File f = File::create(tmp.path());
        f.root().write_string_dataset("job/spec_json", spec);
        f.root().write_string_dataset("job/empty", "");
        f.close();
    }
    File f = File::open_read_only(tmp.path());
    EXPECT_EQ(f.root().open_dataset("job/spec_json").read_string(), spec);
    EXPECT_EQ(f.root().open_dataset("job/empty").read_string(), "");
    EXPECT_TRUE(f.root().open_dataset("job/spec_json").shape().empty()); // scalar
}

TEST(Hdf5ExtendableDataset, AppendsRowsOfATimeSeriesAcrossReopening)
{
    const TempFile tmp;
    {
        File f = File::create(tmp.path());
        Group series = f.root().create_group("series");
        ExtendableDataset time = series.create_extendable_dataset("time_s", ElementType::f64);
        ExtendableDataset force = series.create_extendable_dataset("plate_force_n", ElementType::f64, 3);
        ExtendableDataset contacts = series.create_extendable_dataset("contact_count", ElementType::u32);
        EXPECT_EQ(time.rows(), 0u);
        EXPECT_EQ(force.columns(), 3u);
        EXPECT_EQ(force.rank(), 2);
        for (int k = 0; k < 5; ++k) {
            const double t = 1e-3 * k;
            time.append(std::span<const double>(&t, 1));
            const Vec3 fz(0.0, 0.0, -10.0 * k);
            force.append(std::span<const Vec3>(&fz, 1));
            const std::uint32_t n = 100u + static_cast<std::uint32_t>(k);
            contacts.append(std::span<const std::uint32_t>(&n, 1));
        }
        EXPECT_EQ(time.rows(), 5u);
        EXPECT_EQ(deflate_level(time), 4);
        EXPECT_THROW(force.append(std::vector<double>{1.0, 2.0}), Hdf5Error); // not whole rows
    }
    {
        File f = File::open_read_write(tmp.path());
        ExtendableDataset time = f.root().open_extendable_dataset("series/time_s");
        time.append(std::vector<double>{5e-3, 6e-3});
        EXPECT_THROW((void)f.root().open_extendable_dataset("/"), Hdf5Error); // a group, not a dataset
    }
    File f = File::open_read_only(tmp.path());
    const Group series = f.root().open_group("series");
    EXPECT_EQ(series.open_dataset("time_s").read_doubles(), (std::vector<double>{0, 1e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3}));
    EXPECT_EQ(series.open_dataset("plate_force_n").shape(), (std::vector<std::size_t>{5, 3}));
    EXPECT_EQ(series.open_dataset("plate_force_n").read_doubles()[3 * 4 + 2], -40.0);
    EXPECT_EQ(series.open_dataset("contact_count").read_int64s(), (std::vector<std::int64_t>{100, 101, 102, 103, 104}));
}

TEST(Hdf5Error, MissingFileThrowsWithTheFileNameAndPrintsNothing)
{
    const std::string missing = "/nonexistent-wiredem-dir/run.h5";
    testing::internal::CaptureStderr();
    try {
        (void)File::open_read_only(missing);
        ADD_FAILURE() << "expected Hdf5Error";
    } catch (const Hdf5Error& e) {
        EXPECT_EQ(e.file(), missing);
        EXPECT_EQ(e.object_path(), "/");
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), ""); // H5Eset_auto2 silenced HDF5
}

TEST(Hdf5Error, MissingObjectsAndDuplicatesNameTheHdf5Path)
{
    const TempFile tmp;
    File f = File::create(tmp.path());
    Group root = f.root();
    Group g = root.create_group("tests/0");
    g.write_dataset("q_pa", std::vector<double>{1.0});
    testing::internal::CaptureStderr();
    try {
        (void)g.open_dataset("nope");
        ADD_FAILURE() << "expected Hdf5Error";
    } catch (const Hdf5Error& e) {
        EXPECT_EQ(e.object_path(), "/tests/0/nope");
        EXPECT_NE(std::string(e.what()).find(":/tests/0/nope: cannot open dataset"), std::string::npos) << e.what();
    }
    try {
        g.write_dataset("q_pa", std::vector<double>{2.0});
        ADD_FAILURE() << "expected Hdf5Error";
    } catch (const Hdf5Error& e) {
        EXPECT_EQ(e.object_path(), "/tests/0/q_pa");
    }
    EXPECT_THROW(root.create_group("tests/0"), Hdf5Error);
    EXPECT_THROW((void)root.read_double_attribute("absent"), Hdf5Error);
    EXPECT_THROW((void)g.open_dataset("q_pa").read_string(), Hdf5Error); // numbers are not text
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(Hdf5Error, MisuseIsReportedBeforeAnythingIsWritten)
{
    const TempFile tmp;
    File f = File::create(tmp.path());
    Group root = f.root();
    EXPECT_THROW(root.write_dataset("bad", std::vector<double>(7, 0.0), 3), Hdf5Error); // 7 % 3 ≠ 0
    EXPECT_THROW(root.write_dataset("zero", std::vector<double>{}, 0), Hdf5Error);
    EXPECT_THROW(root.write_string_attribute("nul", std::string("a\0b", 3)), Hdf5Error);
    EXPECT_FALSE(root.exists("bad"));
    EXPECT_FALSE(root.exists("zero"));
}

TEST(Hdf5Dump, CanDumpTheWrittenFile)
{
    const char* h5dump = "/usr/bin/h5dump";
    if (!std::filesystem::exists(h5dump)) GTEST_SKIP() << "h5dump not installed";
    const TempFile tmp;
    const TempFile listing(".txt");
    {
        File f = File::create(tmp.path());
        Group root = f.root();
        root.write_string_attribute("engine", "wiredem");
        Dataset q = root.create_group("tests/0").write_dataset("deviatoric_stress_pa", std::vector<double>{1.0, 2.5, 2.0});
        q.write_string_attribute("units", "Pa");
        root.write_dataset("empty", std::span<const double>{});
        root.write_string_dataset("job/spec_json", "{\"seed\": 7}");
        ExtendableDataset t = root.create_extendable_dataset("time_s", ElementType::f64);
        t.append(std::vector<double>{0.0, 1e-3});
    }
    const std::string command
        = std::string(h5dump) + " -p '" + tmp.path().string() + "' > '" + listing.path().string() + "' 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(listing.path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("deviatoric_stress_pa"), std::string::npos) << text;
    EXPECT_NE(text.find("DEFLATE"), std::string::npos) << text;
    EXPECT_NE(text.find("\"Pa\""), std::string::npos) << text;
    EXPECT_NE(text.find("seed"), std::string::npos) << text;
}
