// SQLite job table. Each public member holds the mutex for its whole
// transaction, so check-then-write sequences (queue bound, idempotency key,
// conditional state moves) are atomic.
#include "job_store.hpp"

#include "io/atomic_file.hpp"

#include <sqlite3.h>

#include <cerrno>
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

namespace wiredem::server {
namespace {

/// A full disk (SQLITE_FULL, or a write that met ENOSPC or EDQUOT) is an
/// io::WriteError naming the database file, which the router answers with
/// 507 (router.cpp); anything else a runtime_error with SQLite's message.
[[noreturn]] void fail(sqlite3* db, const std::string& what)
{
    if (db) {
        const int code = sqlite3_errcode(db);
        const int system_errno = sqlite3_system_errno(db);
        const bool full = code == SQLITE_FULL || (code == SQLITE_IOERR && (system_errno == ENOSPC || system_errno == EDQUOT));
        if (full) {
            const char* file = sqlite3_db_filename(db, "main");
            throw engine::io::WriteError(system_errno == EDQUOT ? EDQUOT : ENOSPC, file ? file : "the job store");
        }
    }
    throw std::runtime_error("sqlite: " + what + ": " + (db ? sqlite3_errmsg(db) : "out of memory"));
}

void exec(sqlite3* db, const char* sql)
{
    char* err = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &err) != SQLITE_OK) {
        std::string msg = err ? err : "unknown error";
        sqlite3_free(err);
        if (sqlite3_errcode(db) == SQLITE_FULL) fail(db, sql);
        throw std::runtime_error(std::string("sqlite: ") + msg + " in: " + sql);
    }
}

/// A prepared statement, finalised on scope exit; bind() indexes from 1.
class Statement {
public:
    Statement(sqlite3* db, const char* sql) : db_(db)
    {
        if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK) fail(db, sql);
    }
    ~Statement() { sqlite3_finalize(stmt_); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;

    Statement& bind(int i, const std::string& s)
    {
        check(sqlite3_bind_text(stmt_, i, s.data(), static_cast<int>(s.size()), SQLITE_TRANSIENT));
        return *this;
    }
    Statement& bind(int i, std::string_view s) { return bind(i, std::string(s)); }
    Statement& bind(int i, const char* s) { return bind(i, std::string(s)); }
    Statement& bind(int i, std::int64_t v)
    {
        check(sqlite3_bind_int64(stmt_, i, v));
        return *this;
    }
    Statement& bind(int i, int v) { return bind(i, static_cast<std::int64_t>(v)); }
    Statement& bind(int i, double v)
    {
        check(sqlite3_bind_double(stmt_, i, v));
        return *this;
    }
    template <class T>
    Statement& bind(int i, const std::optional<T>& v)
    {
        if (v) return bind(i, *v);
        check(sqlite3_bind_null(stmt_, i));
        return *this;
    }

    /// Steps once: true while a row is available.
    bool step()
    {
        const int rc = sqlite3_step(stmt_);
        if (rc == SQLITE_ROW) return true;
        if (rc == SQLITE_DONE) return false;
        fail(db_, "step");
    }
    void run()
    {
        while (step()) {
        }
    }

    std::string text(int col) const
    {
        const auto* p = sqlite3_column_text(stmt_, col);
        return p ? std::string(reinterpret_cast<const char*>(p),
                       static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col)))
                 : std::string();
    }
    std::int64_t int64(int col) const { return sqlite3_column_int64(stmt_, col); }
    double real(int col) const { return sqlite3_column_double(stmt_, col); }
    bool is_null(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }
    std::optional<double> opt_real(int col) const
    {
        return is_null(col) ? std::nullopt : std::optional<double>(real(col));
    }
    std::optional<std::int64_t> opt_int64(int col) const
    {
        return is_null(col) ? std::nullopt : std::optional<std::int64_t>(int64(col));
    }

private:
    void check(int rc)
    {
        if (rc != SQLITE_OK) fail(db_, "bind");
    }
    sqlite3* db_;
    sqlite3_stmt* stmt_ = nullptr;
};

/// BEGIN IMMEDIATE … COMMIT, rolled back if the scope is left by an exception.
class Transaction {
public:
    explicit Transaction(sqlite3* db) : db_(db) { exec(db_, "BEGIN IMMEDIATE"); }
    ~Transaction()
    {
        if (!done_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    }
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    void commit()
    {
        exec(db_, "COMMIT");
        done_ = true;
    }

private:
    sqlite3* db_;
    bool done_ = false;
};

/// What a list shows of a job: every column before the spec, which lists
/// never read (a spec may hold a comment of 10⁴ characters; the columns after
/// it would make SQLite read through its overflow pages).
constexpr const char* list_columns =
    "seq, id, state, stage, progress, eta_s, message, error, attempts, created_ms, started_ms, "
    "finished_ms, name";
/// The whole row.
constexpr const char* columns =
    "seq, id, state, stage, progress, eta_s, message, error, attempts, created_ms, started_ms, "
    "finished_ms, name, spec, idempotency_key, body_steps_per_second";

/// A row of list_columns.
JobRecord read_list_row(const Statement& s)
{
    JobRecord r;
    r.seq = s.int64(0);
    r.id = s.text(1);
    r.state = job_state_from_string(s.text(2)).value_or(JobState::failed);
    r.stage = s.text(3);
    r.progress = s.real(4);
    r.eta_s = s.opt_real(5);
    r.message = s.text(6);
    r.error = s.text(7);
    r.attempts = static_cast<int>(s.int64(8));
    r.created_ms = s.int64(9);
    r.started_ms = s.opt_int64(10);
    r.finished_ms = s.opt_int64(11);
    r.name = s.text(12);
    return r;
}

/// A row of columns.
JobRecord read_row(const Statement& s)
{
    JobRecord r = read_list_row(s);
    r.spec_json = s.text(13);
    r.idempotency_key = s.text(14);
    r.body_steps_per_second = s.opt_real(15);
    return r;
}

/// The job table. `name` comes before `spec` (see list_columns).
constexpr const char* jobs_table_columns =
    " seq INTEGER PRIMARY KEY AUTOINCREMENT,"
    " id TEXT NOT NULL UNIQUE,"
    " state TEXT NOT NULL,"
    " stage TEXT NOT NULL DEFAULT '',"
    " progress REAL NOT NULL DEFAULT 0,"
    " eta_s REAL,"
    " message TEXT NOT NULL DEFAULT '',"
    " error TEXT NOT NULL DEFAULT '',"
    " attempts INTEGER NOT NULL DEFAULT 0,"
    " created_ms INTEGER NOT NULL,"
    " started_ms INTEGER,"
    " finished_ms INTEGER,"
    " name TEXT NOT NULL DEFAULT '',"
    " spec TEXT NOT NULL,"
    " idempotency_key TEXT UNIQUE,"
    " body_steps_per_second REAL";

/// Stores of earlier versions have no `name` column: the table is rebuilt
/// with it (before the spec), filled from each spec, in one transaction.
void add_name_column(sqlite3* db)
{
    bool has_name = false;
    {
        Statement s(db, "PRAGMA table_info(jobs)");
        while (s.step()) has_name = has_name || s.text(1) == "name";
    }
    if (has_name) return;
    Transaction tx(db);
    exec(db, (std::string("CREATE TABLE jobs_with_name (") + jobs_table_columns + ")").c_str());
    exec(db,
        "INSERT INTO jobs_with_name (seq, id, state, stage, progress, eta_s, message, error, attempts, created_ms,"
        " started_ms, finished_ms, name, spec, idempotency_key, body_steps_per_second)"
        " SELECT seq, id, state, stage, progress, eta_s, message, error, attempts, created_ms, started_ms,"
        " finished_ms, COALESCE(CASE WHEN json_valid(spec) THEN json_extract(spec, '$.name') END, ''), spec,"
        " idempotency_key, body_steps_per_second FROM jobs");
    exec(db, "DROP TABLE jobs");
    exec(db, "ALTER TABLE jobs_with_name RENAME TO jobs");
    tx.commit();
}

std::optional<JobRecord> get_locked(sqlite3* db, const std::string& id)
{
    Statement s(db, (std::string("SELECT ") + columns + " FROM jobs WHERE id = ?").c_str());
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    return read_row(s);
}

} // namespace

JobStore::JobStore(const std::filesystem::path& db_file)
{
    const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX;
    if (sqlite3_open_v2(db_file.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
        std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
        sqlite3_close(db_);
        throw std::runtime_error("cannot open " + db_file.string() + ": " + msg);
    }
    try {
        sqlite3_busy_timeout(db_, 5000);
        // WAL: readers never block the writer; FULL: a commit is on disk before
        // we answer 201 (kill -9 and power loss both keep accepted jobs).
        exec(db_, "PRAGMA journal_mode=WAL");
        exec(db_, "PRAGMA synchronous=FULL");
        // Foreign keys on only after add_name_column: its DROP TABLE would
        // otherwise check study_jobs' references to the old table.
        exec(db_, (std::string("CREATE TABLE IF NOT EXISTS jobs (") + jobs_table_columns + ")").c_str());
        add_name_column(db_);
        exec(db_, "PRAGMA foreign_keys=ON");
        exec(db_, "CREATE INDEX IF NOT EXISTS jobs_by_state ON jobs(state, seq)");
        // Studies: a document and its jobs, one per point (added to stores of
        // earlier versions as they open: CREATE … IF NOT EXISTS).
        exec(db_,
            "CREATE TABLE IF NOT EXISTS studies ("
            " seq INTEGER PRIMARY KEY AUTOINCREMENT,"
            " id TEXT NOT NULL UNIQUE,"
            " name TEXT NOT NULL,"
            " created_ms INTEGER NOT NULL,"
            " document TEXT NOT NULL)");
        exec(db_,
            "CREATE TABLE IF NOT EXISTS study_jobs ("
            " study_id TEXT NOT NULL REFERENCES studies(id),"
            " point INTEGER NOT NULL,"
            " job_id TEXT NOT NULL UNIQUE REFERENCES jobs(id),"
            " PRIMARY KEY (study_id, point))");
        // The Slurm jobs of each job run by `--executor slurm`
        // (server/slurm.hpp), added the same way.
        exec(db_,
            "CREATE TABLE IF NOT EXISTS slurm_jobs ("
            " job_id TEXT PRIMARY KEY REFERENCES jobs(id),"
            " prepare INTEGER NOT NULL,"
            " tests INTEGER NOT NULL,"
            " analyse INTEGER NOT NULL,"
            " submitted_ms INTEGER NOT NULL)");
        // A damaged file must stop the server with a message, not abort it at
        // the first read of a bad page (SQLITE_CORRUPT deep in a query).
        Statement check(db_, "PRAGMA quick_check");
        std::string verdict;
        while (check.step()) verdict += (verdict.empty() ? "" : "; ") + check.text(0);
        if (verdict != "ok") throw std::runtime_error("damaged (" + verdict + ")");
        // Every id names a folder under DATA_DIR/jobs: one that is not 24 hex
        // digits (written by anything but this server) could point outside it.
        Statement ids(db_, "SELECT id FROM jobs UNION ALL SELECT id FROM studies");
        while (ids.step())
            if (const std::string id = ids.text(0); !is_valid_job_id(id))
                throw std::runtime_error("damaged (a job id '" + id.substr(0, 64) + "' is not 24 hex digits)");
    } catch (const std::exception& e) {
        sqlite3_close(db_);
        throw std::runtime_error("the job store " + db_file.string() + " cannot be used: " + e.what()
                                 + "; restore it from a backup");
    }
}

JobStore::~JobStore() { sqlite3_close(db_); }

namespace {

/// A study's jobs, by point.
std::vector<std::string> study_job_ids_locked(sqlite3* db, const std::string& id)
{
    Statement j(db, "SELECT job_id FROM study_jobs WHERE study_id = ? ORDER BY point");
    j.bind(1, id);
    std::vector<std::string> ids;
    while (j.step()) ids.push_back(j.text(0));
    return ids;
}

std::optional<StudyRecord> get_study_locked(sqlite3* db, const std::string& id)
{
    Statement s(db, "SELECT seq, id, name, created_ms, document FROM studies WHERE id = ?");
    s.bind(1, id);
    if (!s.step()) return std::nullopt;
    StudyRecord r;
    r.seq = s.int64(0);
    r.id = s.text(1);
    r.name = s.text(2);
    r.created_ms = s.int64(3);
    r.document_json = s.text(4);
    r.job_ids = study_job_ids_locked(db, id);
    return r;
}

} // namespace

InsertOutcome JobStore::insert_study(
    const StudyRecord& study, const std::vector<JobRecord>& jobs, std::size_t max_queued, StudyRecord& out)
{
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    {
        Statement s(db_, "SELECT COUNT(*) FROM jobs WHERE state = 'queued'");
        s.step();
        if (static_cast<std::size_t>(s.int64(0)) + jobs.size() > max_queued) return InsertOutcome::queue_full;
    }
    {
        Statement s(db_, "INSERT INTO studies (id, name, created_ms, document) VALUES (?, ?, ?, ?)");
        s.bind(1, study.id).bind(2, study.name).bind(3, study.created_ms).bind(4, study.document_json);
        s.run();
    }
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        Statement j(db_, "INSERT INTO jobs (id, state, created_ms, name, spec) VALUES (?, 'queued', ?, ?, ?)");
        j.bind(1, jobs[k].id).bind(2, jobs[k].created_ms).bind(3, jobs[k].name).bind(4, jobs[k].spec_json);
        j.run();
        Statement l(db_, "INSERT INTO study_jobs (study_id, point, job_id) VALUES (?, ?, ?)");
        l.bind(1, study.id).bind(2, static_cast<std::int64_t>(k)).bind(3, jobs[k].id);
        l.run();
    }
    out = *get_study_locked(db_, study.id);
    tx.commit();
    return InsertOutcome::created;
}

std::optional<StudyRecord> JobStore::get_study(const std::string& id)
{
    std::lock_guard lock(mutex_);
    return get_study_locked(db_, id);
}

std::vector<StudyListRow> JobStore::list_studies(std::int64_t before_seq, int limit)
{
    std::lock_guard lock(mutex_);
    // The columns before `document` only (the last: SQLite stops short of its
    // overflow pages), and the jobs counted by state through the index of
    // study_jobs' primary key; no spec is read.
    Statement s(db_, "SELECT seq, id, name, created_ms FROM studies WHERE seq < ? ORDER BY seq DESC LIMIT ?");
    s.bind(1, before_seq > 0 ? before_seq : std::numeric_limits<std::int64_t>::max()).bind(2, limit);
    std::vector<StudyListRow> out;
    while (s.step()) {
        StudyListRow r;
        r.seq = s.int64(0);
        r.id = s.text(1);
        r.name = s.text(2);
        r.created_ms = s.int64(3);
        out.push_back(std::move(r));
    }
    for (StudyListRow& r : out) {
        Statement c(db_, "SELECT jobs.state, COUNT(*) FROM study_jobs JOIN jobs ON jobs.id = study_jobs.job_id"
                         " WHERE study_jobs.study_id = ? GROUP BY jobs.state");
        c.bind(1, r.id);
        while (c.step())
            if (auto st = job_state_from_string(c.text(0))) r.jobs_by_state[static_cast<std::size_t>(*st)] = c.int64(1);
        Statement n(db_, "SELECT COUNT(*) FROM study_jobs WHERE study_id = ?");
        n.bind(1, r.id);
        if (n.step()) r.points = static_cast<std::size_t>(n.int64(0));
    }
    return out;
}

namespace {

/// Deletes a study, its points and its jobs (in the caller's transaction).
void delete_study_locked(sqlite3* db, const std::string& id, const std::vector<std::string>& job_ids)
{
    Statement p(db, "DELETE FROM study_jobs WHERE study_id = ?");
    p.bind(1, id).run();
    for (const auto& job : job_ids) {
        Statement sl(db, "DELETE FROM slurm_jobs WHERE job_id = ?");
        sl.bind(1, job).run();
        Statement j(db, "DELETE FROM jobs WHERE id = ?");
        j.bind(1, job).run();
    }
    Statement st(db, "DELETE FROM studies WHERE id = ?");
    st.bind(1, id).run();
}

/// Whether every job of the study has ended.
bool study_ended_locked(sqlite3* db, const std::string& id)
{
    Statement s(db, "SELECT 1 FROM study_jobs JOIN jobs ON jobs.id = study_jobs.job_id WHERE study_jobs.study_id = ?"
                    " AND jobs.state NOT IN ('succeeded', 'failed', 'cancelled') LIMIT 1");
    s.bind(1, id);
    return !s.step();
}

} // namespace

RemoveOutcome JobStore::remove_study(const std::string& id, std::vector<std::string>& job_ids)
{
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    {
        Statement s(db_, "SELECT 1 FROM studies WHERE id = ?");
        s.bind(1, id);
        if (!s.step()) return RemoveOutcome::not_found;
    }
    if (!study_ended_locked(db_, id)) return RemoveOutcome::not_final;
    std::vector<std::string> ids = study_job_ids_locked(db_, id);
    delete_study_locked(db_, id, ids);
    tx.commit();
    job_ids = std::move(ids);
    return RemoveOutcome::removed;
}

InsertOutcome JobStore::insert(const JobRecord& job, std::size_t max_queued, JobRecord& out)
{
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    if (!job.idempotency_key.empty()) {
        Statement s(db_, (std::string("SELECT ") + columns + " FROM jobs WHERE idempotency_key = ?").c_str());
        s.bind(1, job.idempotency_key);
        if (s.step()) {
            out = read_row(s);
            return out.spec_json == job.spec_json ? InsertOutcome::replayed
                                                  : InsertOutcome::idempotency_conflict;
        }
    }
    {
        Statement s(db_, "SELECT COUNT(*) FROM jobs WHERE state = 'queued'");
        s.step();
        if (static_cast<std::size_t>(s.int64(0)) >= max_queued) return InsertOutcome::queue_full;
    }
    {
        Statement s(db_,
            "INSERT INTO jobs (id, state, created_ms, name, spec, idempotency_key) VALUES (?, 'queued', ?, ?, ?, ?)");
        s.bind(1, job.id).bind(2, job.created_ms).bind(3, job.name).bind(4, job.spec_json);
        s.bind(5, job.idempotency_key.empty() ? std::optional<std::string>()
                                              : std::optional<std::string>(job.idempotency_key));
        s.run();
    }
    out = *get_locked(db_, job.id);
    tx.commit();
    return InsertOutcome::created;
}

std::optional<JobRecord> JobStore::get(const std::string& id)
{
    std::lock_guard lock(mutex_);
    return get_locked(db_, id);
}

std::vector<JobRecord> JobStore::list(std::optional<JobState> state, std::int64_t before_seq, int limit)
{
    std::lock_guard lock(mutex_);
    std::string sql = std::string("SELECT ") + list_columns + " FROM jobs WHERE seq < ?";
    if (state) sql += " AND state = ?";
    sql += " ORDER BY seq DESC LIMIT ?";
    Statement s(db_, sql.c_str());
    int i = 1;
    s.bind(i++, before_seq > 0 ? before_seq : std::numeric_limits<std::int64_t>::max());
    if (state) s.bind(i++, to_string(*state));
    s.bind(i, limit);
    std::vector<JobRecord> rows;
    while (s.step()) rows.push_back(read_list_row(s));
    return rows;
}

std::optional<JobRecord> JobStore::claim_next()
{
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    std::string id;
    {
        Statement s(db_, "SELECT id FROM jobs WHERE state = 'queued' ORDER BY seq LIMIT 1");
        if (!s.step()) return std::nullopt;
        id = s.text(0);
    }
    Statement u(db_,
        "UPDATE jobs SET state = 'preparing', stage = '', progress = 0, eta_s = NULL, message = '',"
        " attempts = attempts + 1, started_ms = ? WHERE id = ?");
    u.bind(1, now_ms()).bind(2, id).run();
    auto job = get_locked(db_, id);
    tx.commit();
    return job;
}

void JobStore::update_progress(const std::string& id, JobState state, const std::string& stage,
    double progress, std::optional<double> eta_s, const std::string& message)
{
    std::lock_guard lock(mutex_);
    Statement s(db_,
        "UPDATE jobs SET state = ?, stage = ?, progress = ?, eta_s = ?, message = ?"
        " WHERE id = ? AND state IN ('preparing', 'running')");
    s.bind(1, to_string(state)).bind(2, stage).bind(3, progress).bind(4, eta_s).bind(5, message).bind(6, id);
    s.run();
}

bool JobStore::finish(const std::string& id, JobState final_state, const std::string& error,
    std::optional<double> body_steps_per_second)
{
    std::lock_guard lock(mutex_);
    Statement s(db_,
        "UPDATE jobs SET state = ?, error = ?, finished_ms = ?, eta_s = NULL,"
        " progress = CASE WHEN ? = 'succeeded' THEN 1.0 ELSE progress END,"
        " body_steps_per_second = ? WHERE id = ? AND state IN ('preparing', 'running')");
    s.bind(1, to_string(final_state)).bind(2, error).bind(3, now_ms()).bind(4, to_string(final_state));
    s.bind(5, body_steps_per_second).bind(6, id).run();
    return sqlite3_changes(db_) > 0;
}

CancelOutcome JobStore::cancel(const std::string& id)
{
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    auto job = get_locked(db_, id);
    if (!job) return CancelOutcome::not_found;
    if (job->state == JobState::cancelled) return CancelOutcome::already_cancelled;
    if (is_final(job->state)) return CancelOutcome::already_final;
    Statement s(db_, "UPDATE jobs SET state = 'cancelled', finished_ms = ?, eta_s = NULL, "
                     "error = 'cancelled by request' WHERE id = ?");
    s.bind(1, now_ms()).bind(2, id).run();
    tx.commit();
    return CancelOutcome::cancelled;
}

RemoveOutcome JobStore::remove(const std::string& id)
{
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    auto job = get_locked(db_, id);
    if (!job) return RemoveOutcome::not_found;
    if (!is_final(job->state)) return RemoveOutcome::not_final;
    {
        Statement s(db_, "SELECT 1 FROM study_jobs WHERE job_id = ?");
        s.bind(1, id);
        if (s.step()) return RemoveOutcome::in_study;
    }
    Statement s(db_, "DELETE FROM jobs WHERE id = ?");
    s.bind(1, id).run();
    tx.commit();
    return RemoveOutcome::removed;
}

std::vector<std::string> JobStore::remove_finished_beyond(std::size_t keep)
{
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    // (job, its study or "") beyond the bound, most recently ended first.
    std::vector<std::pair<std::string, std::string>> beyond;
    {
        Statement s(db_,
            "SELECT jobs.id, COALESCE(study_jobs.study_id, '') FROM jobs LEFT JOIN study_jobs ON study_jobs.job_id = jobs.id"
            " WHERE jobs.state IN ('succeeded', 'failed', 'cancelled')"
            " ORDER BY jobs.finished_ms DESC, jobs.seq DESC LIMIT -1 OFFSET ?");
        s.bind(1, static_cast<std::int64_t>(keep));
        while (s.step()) beyond.emplace_back(s.text(0), s.text(1));
    }
    std::vector<std::string> ids;
    std::vector<std::string> studies_seen;
    for (const auto& [id, study] : beyond) {
        if (study.empty()) {
            Statement s(db_, "DELETE FROM jobs WHERE id = ?");
            s.bind(1, id).run();
            ids.push_back(id);
            continue;
        }
        if (std::find(studies_seen.begin(), studies_seen.end(), study) != studies_seen.end()) continue;
        studies_seen.push_back(study);
        if (!study_ended_locked(db_, study)) continue;  // kept whole until its last job ends
        const std::vector<std::string> of_study = study_job_ids_locked(db_, study);
        delete_study_locked(db_, study, of_study);
        ids.insert(ids.end(), of_study.begin(), of_study.end());
    }
    tx.commit();
    return ids;
}

bool JobStore::requeue(const std::string& id) { return back_to_queue(id, false); }

bool JobStore::retry(const std::string& id) { return back_to_queue(id, true); }

bool JobStore::back_to_queue(const std::string& id, bool count_attempt)
{
    std::lock_guard lock(mutex_);
    Statement s(db_, count_attempt
            ? "UPDATE jobs SET state = 'queued', stage = '', progress = 0, eta_s = NULL, message = ''"
              " WHERE id = ? AND state IN ('preparing', 'running')"
            : "UPDATE jobs SET state = 'queued', stage = '', progress = 0, eta_s = NULL, message = '',"
              " attempts = MAX(attempts - 1, 0) WHERE id = ? AND state IN ('preparing', 'running')");
    s.bind(1, id).run();
    return sqlite3_changes(db_) > 0;
}

std::vector<std::string> JobStore::requeue_interrupted()
{
    std::lock_guard lock(mutex_);
    Transaction tx(db_);
    std::vector<std::string> ids;
    {
        Statement s(db_, "SELECT id FROM jobs WHERE state IN ('preparing', 'running') ORDER BY seq");
        while (s.step()) ids.push_back(s.text(0));
    }
    exec(db_, "UPDATE jobs SET state = 'queued', stage = '', progress = 0, eta_s = NULL, message = ''"
              " WHERE state IN ('preparing', 'running')");
    tx.commit();
    return ids;
}

void JobStore::set_slurm_ids(const std::string& job_id, const SlurmIds& ids)
{
    std::lock_guard lock(mutex_);
    Statement s(db_, "INSERT OR REPLACE INTO slurm_jobs (job_id, prepare, tests, analyse, submitted_ms) VALUES (?, ?, ?, ?, ?)");
    s.bind(1, job_id).bind(2, ids.prepare).bind(3, ids.tests).bind(4, ids.analyse).bind(5, ids.submitted_ms).run();
}

std::optional<SlurmIds> JobStore::slurm_ids(const std::string& job_id)
{
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT prepare, tests, analyse, submitted_ms FROM slurm_jobs WHERE job_id = ?");
    s.bind(1, job_id);
    if (!s.step()) return std::nullopt;
    return SlurmIds{s.int64(0), s.int64(1), s.int64(2), s.int64(3)};
}

std::vector<std::string> JobStore::unfinished_with_slurm_ids()
{
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT jobs.id FROM jobs JOIN slurm_jobs ON slurm_jobs.job_id = jobs.id"
                     " WHERE jobs.state IN ('queued', 'preparing', 'running') ORDER BY jobs.seq");
    std::vector<std::string> ids;
    while (s.step()) ids.push_back(s.text(0));
    return ids;
}

void JobStore::clear_slurm_ids(const std::string& job_id)
{
    std::lock_guard lock(mutex_);
    Statement s(db_, "DELETE FROM slurm_jobs WHERE job_id = ?");
    s.bind(1, job_id).run();
}

std::vector<std::string> JobStore::succeeded_ids()
{
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT id FROM jobs WHERE state = 'succeeded' ORDER BY seq");
    std::vector<std::string> ids;
    while (s.step()) ids.push_back(s.text(0));
    return ids;
}

void JobStore::demote_to_failed(const std::string& id, const std::string& error)
{
    std::lock_guard lock(mutex_);
    Statement s(db_, "UPDATE jobs SET state = 'failed', error = ? WHERE id = ? AND state = 'succeeded'");
    s.bind(1, error).bind(2, id).run();
}

StateCounts JobStore::count_by_state()
{
    std::lock_guard lock(mutex_);
    StateCounts counts{};
    Statement s(db_, "SELECT state, COUNT(*) FROM jobs GROUP BY state");
    while (s.step())
        if (auto st = job_state_from_string(s.text(0))) counts[static_cast<std::size_t>(*st)] = s.int64(1);
    return counts;
}

std::optional<double> JobStore::last_body_steps_per_second()
{
    std::lock_guard lock(mutex_);
    Statement s(db_, "SELECT body_steps_per_second FROM jobs WHERE body_steps_per_second IS NOT NULL"
                     " ORDER BY finished_ms DESC, seq DESC LIMIT 1");
    if (!s.step()) return std::nullopt;
    return s.opt_real(0);
}

} // namespace wiredem::server
