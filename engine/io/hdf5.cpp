// RAII layer over the HDF5 C API; see hdf5.hpp for the design and the error policy.
// Every C call goes through check() / check_id(), which turn a negative return into
// an Hdf5Error carrying the file, the object path and HDF5's error stack.
#include "io/hdf5.hpp"

#include "io/atomic_file.hpp"

#include <hdf5.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <type_traits>

namespace wiredem::engine::io {

static_assert(std::is_same_v<hid_t, std::int64_t>, "detail::Handle stores hid_t as int64_t (HDF5 ≥ 1.10)");
static_assert(std::is_same_v<herr_t, int>, "detail::Handle::Closer assumes herr_t is int");

namespace {

/// About 64 KiB per chunk: large enough for deflate to work well, small enough for
/// HDF5's default 1 MiB chunk cache (the HDF5 guide suggests 10 KiB – 1 MiB).
constexpr std::size_t target_chunk_bytes = 64 * 1024;
constexpr unsigned deflate_level = 4;

/// HDF5 prints its error stack to stderr by default; we report through Hdf5Error
/// instead. The setting is per thread in a thread-safe build, hence thread_local.
void silence_automatic_error_printing() noexcept
{
    thread_local bool silenced = false;
    if (!silenced) {
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
        silenced = true;
    }
}

/// The outermost and innermost descriptions on the current error stack, then clears it.
std::string take_error_stack()
{
    struct Collected {
        std::string outer, inner;
    } collected;
    const auto visit = [](unsigned n, const H5E_error2_t* e, void* data) -> herr_t {
        auto* c = static_cast<Collected*>(data);
        const std::string desc = e->desc ? e->desc : "";
        if (n == 0) c->outer = desc;
        c->inner = desc;
        return 0;
    };
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, visit, &collected);
    H5Eclear2(H5E_DEFAULT);
    if (collected.outer.empty() && collected.inner.empty()) return "no HDF5 error description";
    if (collected.inner.empty() || collected.inner == collected.outer) return collected.outer;
    return collected.outer + " (" + collected.inner + ")";
}

/// Where a call happens, for the error message.
struct Where {
    std::string file;
    std::string path;
};

[[noreturn]] void fail(const Where& at, const std::string& action)
{
    throw Hdf5Error(action, at.file, at.path, take_error_stack());
}

[[noreturn]] void misuse(const Where& at, const std::string& action, const std::string& reason)
{
    throw Hdf5Error(action, at.file, at.path, reason);
}

hid_t check_id(hid_t id, const Where& at, const std::string& action)
{
    if (id < 0) fail(at, action);
    return id;
}

void check(herr_t status, const Where& at, const std::string& action)
{
    if (status < 0) fail(at, action);
}

/// A tri-state HDF5 answer (htri_t): > 0 true, 0 false, < 0 error.
bool check_tri(htri_t answer, const Where& at, const std::string& action)
{
    if (answer < 0) fail(at, action);
    return answer > 0;
}

detail::Handle owned(hid_t id, herr_t (*closer)(hid_t)) { return detail::Handle(id, closer); }

std::string join_path(const std::string& parent, std::string_view child)
{
    if (!child.empty() && child.front() == '/') return std::string(child);
    if (child.empty() || child == ".") return parent;
    return parent == "/" ? "/" + std::string(child) : parent + "/" + std::string(child);
}

/// Link creation property list that creates missing intermediate groups.
detail::Handle intermediate_group_lcpl(const Where& at)
{
    detail::Handle lcpl = owned(check_id(H5Pcreate(H5P_LINK_CREATE), at, "cannot create link property list"), H5Pclose);
    check(H5Pset_create_intermediate_group(lcpl.get(), 1), at, "cannot enable intermediate groups");
    return lcpl;
}

/// Variable-length UTF-8 C string type.
detail::Handle vlen_string_type(const Where& at)
{
    detail::Handle t = owned(check_id(H5Tcopy(H5T_C_S1), at, "cannot copy string type"), H5Tclose);
    check(H5Tset_size(t.get(), H5T_VARIABLE), at, "cannot make string type variable-length");
    check(H5Tset_cset(t.get(), H5T_CSET_UTF8), at, "cannot set string character set");
    return t;
}

hid_t file_type(ElementType type)
{
    switch (type) {
    case ElementType::f64: return H5T_IEEE_F64LE;
    case ElementType::i32: return H5T_STD_I32LE;
    case ElementType::i64: return H5T_STD_I64LE;
    case ElementType::u32: return H5T_STD_U32LE;
    case ElementType::u64: return H5T_STD_U64LE;
    }
    return H5I_INVALID_HID;
}

template <class T>
struct Native;
template <>
struct Native<double> {
    static constexpr ElementType element = ElementType::f64;
    static hid_t mem_type() { return H5T_NATIVE_DOUBLE; }
};
template <>
struct Native<std::int32_t> {
    static constexpr ElementType element = ElementType::i32;
    static hid_t mem_type() { return H5T_NATIVE_INT32; }
};
template <>
struct Native<std::int64_t> {
    static constexpr ElementType element = ElementType::i64;
    static hid_t mem_type() { return H5T_NATIVE_INT64; }
};
template <>
struct Native<std::uint32_t> {
    static constexpr ElementType element = ElementType::u32;
    static hid_t mem_type() { return H5T_NATIVE_UINT32; }
};
template <>
struct Native<std::uint64_t> {
    static constexpr ElementType element = ElementType::u64;
    static hid_t mem_type() { return H5T_NATIVE_UINT64; }
};

std::size_t element_bytes(ElementType type) { return (type == ElementType::i32 || type == ElementType::u32) ? 4 : 8; }

/// Rows per chunk: about target_chunk_bytes of whole rows, at least 1; for a fixed
/// extent never more rows than there are (a chunk larger than the data wastes space).
hsize_t chunk_rows(std::size_t rows, std::size_t row_bytes, bool growable)
{
    const std::size_t by_size = std::max<std::size_t>(1, target_chunk_bytes / std::max<std::size_t>(1, row_bytes));
    if (growable) return by_size;
    return std::clamp<std::size_t>(by_size, 1, std::max<std::size_t>(1, rows));
}

/// Creates a chunked, shuffled, deflated dataset of rows (× columns when rank 2).
/// Extendable datasets and empty ones get an unlimited row dimension.
detail::Handle create_numeric_dataset(hid_t loc, const Where& at, std::string_view name, ElementType type,
    std::size_t rows, int rank, std::size_t columns, bool extendable)
{
    if (H5Zfilter_avail(H5Z_FILTER_DEFLATE) <= 0) misuse(at, "cannot create dataset", "deflate filter not available");
    const bool growable = extendable || rows == 0;
    const hsize_t dims[2] = {rows, columns};
    const hsize_t max_dims[2] = {growable ? H5S_UNLIMITED : hsize_t{rows}, columns};
    const hsize_t chunk[2] = {chunk_rows(rows, columns * element_bytes(type), growable), columns};

    detail::Handle space
        = owned(check_id(H5Screate_simple(rank, dims, max_dims), at, "cannot create dataspace"), H5Sclose);
    detail::Handle dcpl
        = owned(check_id(H5Pcreate(H5P_DATASET_CREATE), at, "cannot create dataset property list"), H5Pclose);
    check(H5Pset_chunk(dcpl.get(), rank, chunk), at, "cannot set chunk size");
    check(H5Pset_shuffle(dcpl.get()), at, "cannot set shuffle filter"); // bytes of like significance together
    check(H5Pset_deflate(dcpl.get(), deflate_level), at, "cannot set deflate filter");
    detail::Handle lcpl = intermediate_group_lcpl(at);
    const std::string name_z(name);
    return owned(
        check_id(H5Dcreate2(loc, name_z.c_str(), file_type(type), space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT), at,
            "cannot create dataset"),
        H5Dclose);
}

template <class T>
Dataset write_array(Group& g, std::string_view name, std::span<const T> values, int rank, std::size_t columns)
{
    const std::string path = join_path(g.path(), name);
    const Where at{g.file_name(), path};
    if (rank == 2 && columns == 0) misuse(at, "cannot write dataset", "columns must be at least 1");
    if (rank == 2 && values.size() % columns != 0)
        misuse(at, "cannot write dataset",
            "values.size() = " + std::to_string(values.size())
                + " is not a multiple of columns = " + std::to_string(columns));
    const std::size_t rows = rank == 2 ? values.size() / columns : values.size();
    detail::Handle ds
        = create_numeric_dataset(g.id(), at, name, Native<T>::element, rows, rank, rank == 2 ? columns : 1, false);
    if (rows > 0)
        check(H5Dwrite(ds.get(), Native<T>::mem_type(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), at,
            "cannot write dataset");
    return Dataset(std::move(ds), g.file_name(), path);
}

std::vector<double> flatten(std::span<const Vec3> vectors)
{
    std::vector<double> flat;
    flat.reserve(3 * vectors.size());
    for (const Vec3& v : vectors) flat.insert(flat.end(), {v.x(), v.y(), v.z()});
    return flat;
}

/// Reads a string from an attribute or a dataset of string type with one element;
/// `read(mem_type, buffer)` performs the H5Aread / H5Dread.
template <class Read>
std::string read_string_value(hid_t stored_type, hid_t space, const Where& at, Read read)
{
    if (H5Tget_class(stored_type) != H5T_STRING) misuse(at, "cannot read string", "stored type is not a string");
    const hssize_t points = H5Sget_simple_extent_npoints(space);
    if (points != 1) misuse(at, "cannot read string", "expected one string, found " + std::to_string(points));
    if (check_tri(H5Tis_variable_str(stored_type), at, "cannot inspect string type")) {
        detail::Handle mem = vlen_string_type(at);
        char* text = nullptr;
        check(read(mem.get(), static_cast<void*>(&text)), at, "cannot read string");
        std::string out = text ? text : "";
        H5Dvlen_reclaim(mem.get(), space, H5P_DEFAULT, static_cast<void*>(&text));
        return out;
    }
    const std::size_t size = H5Tget_size(stored_type);
    detail::Handle mem = owned(check_id(H5Tcopy(H5T_C_S1), at, "cannot copy string type"), H5Tclose);
    check(H5Tset_size(mem.get(), size), at, "cannot size string type");
    check(H5Tset_strpad(mem.get(), H5T_STR_NULLPAD), at, "cannot set string padding");
    std::string out(size, '\0');
    check(read(mem.get(), static_cast<void*>(out.data())), at, "cannot read string");
    out.resize(std::min(out.find('\0'), out.size())); // fixed-length strings are NUL padded
    return out;
}

template <class T>
std::vector<T> read_all(hid_t dataset, hid_t mem_type, const Where& at)
{
    detail::Handle space = owned(check_id(H5Dget_space(dataset), at, "cannot get dataspace"), H5Sclose);
    const hssize_t points = H5Sget_simple_extent_npoints(space.get());
    if (points < 0) fail(at, "cannot count elements");
    std::vector<T> out(static_cast<std::size_t>(points));
    if (!out.empty())
        check(H5Dread(dataset, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), at, "cannot read dataset");
    return out;
}

std::vector<std::size_t> extent(hid_t dataset, const Where& at)
{
    detail::Handle space = owned(check_id(H5Dget_space(dataset), at, "cannot get dataspace"), H5Sclose);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank < 0) fail(at, "cannot get rank");
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    if (rank > 0) check(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr), at, "cannot get extent");
    return {dims.begin(), dims.end()};
}

/// Opens an attribute for writing: an existing one is deleted first (its type or
/// shape may differ), then a scalar attribute of file_type is created.
detail::Handle create_scalar_attribute(hid_t object, const Where& at, std::string_view name, hid_t type)
{
    const std::string name_z(name);
    const std::string action = "cannot write attribute '" + name_z + "'";
    if (check_tri(H5Aexists(object, name_z.c_str()), at, action)) check(H5Adelete(object, name_z.c_str()), at, action);
    detail::Handle space = owned(check_id(H5Screate(H5S_SCALAR), at, action), H5Sclose);
    return owned(check_id(H5Acreate2(object, name_z.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), at, action),
        H5Aclose);
}

detail::Handle open_attribute(hid_t object, const Where& at, std::string_view name)
{
    const std::string name_z(name);
    return owned(
        check_id(H5Aopen(object, name_z.c_str(), H5P_DEFAULT), at, "cannot open attribute '" + name_z + "'"), H5Aclose);
}

template <class T>
T read_scalar_attribute(hid_t object, const Where& at, std::string_view name, hid_t mem_type)
{
    detail::Handle attr = open_attribute(object, at, name);
    const std::string action = "cannot read attribute '" + std::string(name) + "'";
    detail::Handle space = owned(check_id(H5Aget_space(attr.get()), at, action), H5Sclose);
    const hssize_t points = H5Sget_simple_extent_npoints(space.get());
    if (points != 1) misuse(at, action, "expected a scalar, found " + std::to_string(points) + " elements");
    T value{};
    check(H5Aread(attr.get(), mem_type, &value), at, action);
    return value;
}

} // namespace

// ---------------------------------------------------------------- Hdf5Error, Handle

Hdf5Error::Hdf5Error(const std::string& action, std::string file, std::string object_path, const std::string& reason)
    : std::runtime_error(file + ":" + object_path + ": " + action + ": " + reason)
    , file_(std::move(file))
    , object_path_(std::move(object_path))
{
}

namespace detail {

Handle::Handle(Handle&& other) noexcept : id_(other.id_), closer_(other.closer_) { other.id_ = -1; }

Handle& Handle::operator=(Handle&& other) noexcept
{
    if (this != &other) {
        reset();
        id_ = std::exchange(other.id_, -1);
        closer_ = other.closer_;
    }
    return *this;
}

void Handle::reset() noexcept
{
    if (id_ >= 0 && closer_) {
        silence_automatic_error_printing();
        if (closer_(id_) < 0) H5Eclear2(H5E_DEFAULT); // nowhere to report from a destructor
    }
    id_ = -1;
}

std::int64_t Handle::release() noexcept { return std::exchange(id_, -1); }

} // namespace detail

// ---------------------------------------------------------------- Object (attributes)

void Object::write_string_attribute(std::string_view name, std::string_view value)
{
    silence_automatic_error_printing();
    const Where at{file_, path_};
    if (value.find('\0') != std::string_view::npos)
        misuse(at, "cannot write attribute '" + std::string(name) + "'", "value contains a NUL byte");
    detail::Handle type = vlen_string_type(at);
    detail::Handle attr = create_scalar_attribute(id(), at, name, type.get());
    const std::string text(value);
    const char* ptr = text.c_str();
    check(H5Awrite(attr.get(), type.get(), &ptr), at, "cannot write attribute '" + std::string(name) + "'");
}

void Object::write_double_attribute(std::string_view name, double value)
{
    silence_automatic_error_printing();
    const Where at{file_, path_};
    detail::Handle attr = create_scalar_attribute(id(), at, name, H5T_IEEE_F64LE);
    check(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, &value), at, "cannot write attribute '" + std::string(name) + "'");
}

void Object::write_int_attribute(std::string_view name, std::int64_t value)
{
    silence_automatic_error_printing();
    const Where at{file_, path_};
    detail::Handle attr = create_scalar_attribute(id(), at, name, H5T_STD_I64LE);
    check(H5Awrite(attr.get(), H5T_NATIVE_INT64, &value), at, "cannot write attribute '" + std::string(name) + "'");
}

bool Object::has_attribute(std::string_view name) const
{
    silence_automatic_error_printing();
    const std::string name_z(name);
    return check_tri(H5Aexists(id(), name_z.c_str()), Where{file_, path_}, "cannot look up attribute '" + name_z + "'");
}

std::string Object::read_string_attribute(std::string_view name) const
{
    silence_automatic_error_printing();
    const Where at{file_, path_};
    detail::Handle attr = open_attribute(id(), at, name);
    detail::Handle type = owned(check_id(H5Aget_type(attr.get()), at, "cannot get attribute type"), H5Tclose);
    detail::Handle space = owned(check_id(H5Aget_space(attr.get()), at, "cannot get attribute space"), H5Sclose);
    return read_string_value(
        type.get(), space.get(), at, [&](hid_t mem, void* buf) { return H5Aread(attr.get(), mem, buf); });
}

double Object::read_double_attribute(std::string_view name) const
{
    silence_automatic_error_printing();
    return read_scalar_attribute<double>(id(), Where{file_, path_}, name, H5T_NATIVE_DOUBLE);
}

std::int64_t Object::read_int_attribute(std::string_view name) const
{
    silence_automatic_error_printing();
    return read_scalar_attribute<std::int64_t>(id(), Where{file_, path_}, name, H5T_NATIVE_INT64);
}

// ---------------------------------------------------------------- Dataset

std::vector<std::size_t> Dataset::shape() const
{
    silence_automatic_error_printing();
    return extent(id(), Where{file_, path_});
}

std::vector<double> Dataset::read_doubles() const
{
    silence_automatic_error_printing();
    return read_all<double>(id(), H5T_NATIVE_DOUBLE, Where{file_, path_});
}

std::vector<std::int64_t> Dataset::read_int64s() const
{
    silence_automatic_error_printing();
    return read_all<std::int64_t>(id(), H5T_NATIVE_INT64, Where{file_, path_});
}

std::string Dataset::read_string() const
{
    silence_automatic_error_printing();
    const Where at{file_, path_};
    detail::Handle type = owned(check_id(H5Dget_type(id()), at, "cannot get dataset type"), H5Tclose);
    detail::Handle space = owned(check_id(H5Dget_space(id()), at, "cannot get dataspace"), H5Sclose);
    return read_string_value(type.get(), space.get(), at,
        [&](hid_t mem, void* buf) { return H5Dread(id(), mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf); });
}

// ---------------------------------------------------------------- ExtendableDataset

ExtendableDataset::ExtendableDataset(detail::Handle handle, std::string file, std::string path)
    : Dataset(std::move(handle), std::move(file), std::move(path))
{
    silence_automatic_error_printing();
    const Where at{file_, path_};
    detail::Handle space = owned(check_id(H5Dget_space(id()), at, "cannot get dataspace"), H5Sclose);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    if (rank != 1 && rank != 2)
        misuse(at, "cannot open extendable dataset", "rank " + std::to_string(rank) + " is not 1 or 2");
    hsize_t dims[2] = {0, 1}, max_dims[2] = {0, 1};
    check(H5Sget_simple_extent_dims(space.get(), dims, max_dims), at, "cannot get extent");
    if (max_dims[0] != H5S_UNLIMITED) misuse(at, "cannot open extendable dataset", "first dimension is not unlimited");
    rank_ = rank;
    columns_ = rank == 2 ? dims[1] : 1;
}

std::size_t ExtendableDataset::rows() const
{
    silence_automatic_error_printing();
    return extent(id(), Where{file_, path_}).front();
}

void ExtendableDataset::append_raw(const void* data, std::int64_t mem_type, std::size_t count)
{
    silence_automatic_error_printing();
    const Where at{file_, path_};
    if (count % columns_ != 0)
        misuse(at, "cannot append",
            std::to_string(count) + " values is not a multiple of columns = " + std::to_string(columns_));
    const hsize_t added = count / columns_;
    if (added == 0) return;
    const hsize_t old_rows = rows();
    const hsize_t new_dims[2] = {old_rows + added, columns_};
    check(H5Dset_extent(id(), new_dims), at, "cannot extend dataset");

    detail::Handle file_space = owned(check_id(H5Dget_space(id()), at, "cannot get dataspace"), H5Sclose);
    const hsize_t start[2] = {old_rows, 0};
    const hsize_t block[2] = {added, columns_};
    check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, block, nullptr), at,
        "cannot select rows");
    detail::Handle mem_space
        = owned(check_id(H5Screate_simple(rank_, block, nullptr), at, "cannot create dataspace"), H5Sclose);
    check(H5Dwrite(id(), mem_type, mem_space.get(), file_space.get(), H5P_DEFAULT, data), at, "cannot append rows");
}

void ExtendableDataset::append(std::span<const double> rows)
{
    append_raw(rows.data(), H5T_NATIVE_DOUBLE, rows.size());
}
void ExtendableDataset::append(std::span<const std::int32_t> rows)
{
    append_raw(rows.data(), H5T_NATIVE_INT32, rows.size());
}
void ExtendableDataset::append(std::span<const std::int64_t> rows)
{
    append_raw(rows.data(), H5T_NATIVE_INT64, rows.size());
}
void ExtendableDataset::append(std::span<const std::uint32_t> rows)
{
    append_raw(rows.data(), H5T_NATIVE_UINT32, rows.size());
}
void ExtendableDataset::append(std::span<const std::uint64_t> rows)
{
    append_raw(rows.data(), H5T_NATIVE_UINT64, rows.size());
}

void ExtendableDataset::append(std::span<const Vec3> rows)
{
    if (rank_ != 2 || columns_ != 3) misuse(Where{file_, path_}, "cannot append vectors", "dataset is not N x 3");
    const std::vector<double> flat = flatten(rows);
    append_raw(flat.data(), H5T_NATIVE_DOUBLE, flat.size());
}

// ---------------------------------------------------------------- Group

Group Group::create_group(std::string_view path)
{
    silence_automatic_error_printing();
    const std::string full = join_path(path_, path);
    const Where at{file_, full};
    detail::Handle lcpl = intermediate_group_lcpl(at);
    const std::string path_z(path);
    hid_t g
        = check_id(H5Gcreate2(id(), path_z.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), at, "cannot create group");
    return Group(owned(g, H5Gclose), file_, full);
}

Group Group::open_group(std::string_view path) const
{
    silence_automatic_error_printing();
    const std::string full = join_path(path_, path);
    const std::string path_z(path.empty() ? "." : path);
    hid_t g = check_id(H5Gopen2(id(), path_z.c_str(), H5P_DEFAULT), Where{file_, full}, "cannot open group");
    return Group(owned(g, H5Gclose), file_, full);
}

Group Group::require_group(std::string_view path) { return exists(path) ? open_group(path) : create_group(path); }

Dataset Group::open_dataset(std::string_view path) const
{
    silence_automatic_error_printing();
    const std::string full = join_path(path_, path);
    const std::string path_z(path);
    hid_t d = check_id(H5Dopen2(id(), path_z.c_str(), H5P_DEFAULT), Where{file_, full}, "cannot open dataset");
    return Dataset(owned(d, H5Dclose), file_, full);
}

ExtendableDataset Group::open_extendable_dataset(std::string_view path) const
{
    silence_automatic_error_printing();
    const std::string full = join_path(path_, path);
    const std::string path_z(path);
    hid_t d = check_id(H5Dopen2(id(), path_z.c_str(), H5P_DEFAULT), Where{file_, full}, "cannot open dataset");
    return ExtendableDataset(owned(d, H5Dclose), file_, full);
}

bool Group::exists(std::string_view path) const
{
    silence_automatic_error_printing();
    const Where at{file_, join_path(path_, path)};
    // H5Lexists fails (rather than answering false) when an intermediate link is
    // missing, so test each prefix in turn.
    std::string prefix = (!path.empty() && path.front() == '/') ? "/" : "";
    std::size_t pos = 0;
    while (pos < path.size()) {
        const std::size_t next = std::min(path.find('/', pos), path.size());
        const std::string_view component = path.substr(pos, next - pos);
        pos = next + 1;
        if (component.empty() || component == ".") continue;
        if (!prefix.empty() && prefix.back() != '/') prefix += '/';
        prefix += component;
        if (!check_tri(H5Lexists(id(), prefix.c_str(), H5P_DEFAULT), at, "cannot look up link")) return false;
    }
    return true;
}

std::vector<std::string> Group::child_names() const
{
    silence_automatic_error_printing();
    std::vector<std::string> names;
    const auto visit = [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->emplace_back(name);
        return 0;
    };
    check(
        H5Literate(id(), H5_INDEX_NAME, H5_ITER_INC, nullptr, visit, &names), Where{file_, path_}, "cannot list group");
    return names;
}

Dataset Group::write_dataset(std::string_view name, std::span<const double> values)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 1, 1);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::int32_t> values)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 1, 1);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::int64_t> values)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 1, 1);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::uint32_t> values)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 1, 1);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::uint64_t> values)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 1, 1);
}

Dataset Group::write_dataset(std::string_view name, std::span<const double> values, std::size_t columns)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 2, columns);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::int32_t> values, std::size_t columns)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 2, columns);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::int64_t> values, std::size_t columns)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 2, columns);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::uint32_t> values, std::size_t columns)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 2, columns);
}

Dataset Group::write_dataset(std::string_view name, std::span<const std::uint64_t> values, std::size_t columns)
{
    silence_automatic_error_printing();
    return write_array(*this, name, values, 2, columns);
}

Dataset Group::write_dataset(std::string_view name, std::span<const Vec3> vectors)
{
    silence_automatic_error_printing();
    const std::vector<double> flat = flatten(vectors);
    return write_array(*this, name, std::span<const double>(flat), 2, 3);
}

Dataset Group::write_string_dataset(std::string_view name, std::string_view text)
{
    silence_automatic_error_printing();
    const std::string full = join_path(path_, name);
    const Where at{file_, full};
    if (text.find('\0') != std::string_view::npos)
        misuse(at, "cannot write string dataset", "text contains a NUL byte");
    detail::Handle type = vlen_string_type(at);
    detail::Handle space = owned(check_id(H5Screate(H5S_SCALAR), at, "cannot create dataspace"), H5Sclose);
    detail::Handle lcpl = intermediate_group_lcpl(at);
    const std::string name_z(name);
    detail::Handle ds = owned(
        check_id(H5Dcreate2(id(), name_z.c_str(), type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), at,
            "cannot create string dataset"),
        H5Dclose);
    const std::string copy(text);
    const char* ptr = copy.c_str();
    check(H5Dwrite(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &ptr), at, "cannot write string dataset");
    return Dataset(std::move(ds), file_, full);
}

ExtendableDataset Group::create_extendable_dataset(std::string_view name, ElementType type)
{
    silence_automatic_error_printing();
    const std::string full = join_path(path_, name);
    detail::Handle ds = create_numeric_dataset(id(), Where{file_, full}, name, type, 0, 1, 1, true);
    return ExtendableDataset(std::move(ds), file_, full);
}

ExtendableDataset Group::create_extendable_dataset(std::string_view name, ElementType type, std::size_t columns)
{
    silence_automatic_error_printing();
    const std::string full = join_path(path_, name);
    if (columns == 0) misuse(Where{file_, full}, "cannot create dataset", "columns must be at least 1");
    detail::Handle ds = create_numeric_dataset(id(), Where{file_, full}, name, type, 0, 2, columns, true);
    return ExtendableDataset(std::move(ds), file_, full);
}

// ---------------------------------------------------------------- File

File File::create(const std::filesystem::path& path)
{
    silence_automatic_error_printing();
    const std::string name = path.string();
    hid_t f = check_id(
        H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), Where{name, "/"}, "cannot create file");
    return File(owned(f, H5Fclose), name);
}

File File::open_read_only(const std::filesystem::path& path)
{
    silence_automatic_error_printing();
    const std::string name = path.string();
    hid_t f
        = check_id(H5Fopen(name.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), Where{name, "/"}, "cannot open file read-only");
    return File(owned(f, H5Fclose), name);
}

File File::open_read_write(const std::filesystem::path& path)
{
    silence_automatic_error_printing();
    const std::string name = path.string();
    hid_t f
        = check_id(H5Fopen(name.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), Where{name, "/"}, "cannot open file read-write");
    return File(owned(f, H5Fclose), name);
}

File File::create_in_memory(const std::filesystem::path& name_path)
{
    silence_automatic_error_printing();
    const std::string name = name_path.string();
    const Where at{name, "/"};
    detail::Handle fapl = owned(check_id(H5Pcreate(H5P_FILE_ACCESS), at, "cannot create file access list"), H5Pclose);
    // Grows by 1 MiB; no backing store: the file never reaches the disk.
    check(H5Pset_fapl_core(fapl.get(), std::size_t{1} << 20, 0), at, "cannot select the in-memory driver");
    hid_t f = check_id(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), at, "cannot create file in memory");
    return File(owned(f, H5Fclose), name);
}

std::string File::image()
{
    silence_automatic_error_printing();
    const Where at{name_, "/"};
    if (id() < 0) misuse(at, "cannot take the file's image", "file is closed");
    check(H5Fflush(id(), H5F_SCOPE_GLOBAL), at, "cannot flush file");
    const ssize_t size = H5Fget_file_image(id(), nullptr, 0);
    if (size < 0) fail(at, "cannot size the file's image");
    std::string bytes(static_cast<std::size_t>(size), '\0');
    if (H5Fget_file_image(id(), bytes.data(), bytes.size()) != size) fail(at, "cannot take the file's image");
    return bytes;
}

Group File::root() const
{
    silence_automatic_error_printing();
    const Where at{name_, "/"};
    if (id() < 0) misuse(at, "cannot open root group", "file is closed");
    return Group(owned(check_id(H5Gopen2(id(), "/", H5P_DEFAULT), at, "cannot open root group"), H5Gclose), name_, "/");
}

void File::flush()
{
    silence_automatic_error_printing();
    const Where at{name_, "/"};
    if (id() < 0) misuse(at, "cannot flush", "file is closed");
    check(H5Fflush(id(), H5F_SCOPE_GLOBAL), at, "cannot flush file");
}

void File::close()
{
    silence_automatic_error_printing();
    if (id() < 0) return;
    const Where at{name_, "/"};
    // The file's own identifier counts one.
    const ssize_t open_objects = H5Fget_obj_count(id(), H5F_OBJ_ALL | H5F_OBJ_LOCAL);
    if (open_objects < 0) fail(at, "cannot count the file's open objects");
    if (open_objects > 1)
        misuse(at, "cannot close file",
            std::to_string(open_objects - 1) + " group(s), dataset(s) or attribute(s) opened through it are still open");
    check(H5Fclose(handle_.release()), at, "cannot close file");
}

void write_file_atomically(const std::filesystem::path& path, const std::function<void(Group& root)>& write)
{
    replace_file_atomically(path, [&](const std::filesystem::path& partial) {
        std::string bytes;
        {
            File file = File::create_in_memory(path);
            {
                Group root = file.root();
                write(root);
            }
            bytes = file.image();
            file.close();
        }
        write_file_bytes(partial, bytes, path);
    });
}

} // namespace wiredem::engine::io
