// wiredem: the command-line client of wiredem-server, and the local runner
// (`wiredem run`). Errors end as one line "wiredem: …" on stderr and an exit
// code from exit_codes.hpp (table in docs/client.md).
#include "commands.hpp"
#include "api/study.hpp"
#include "exit_codes.hpp"
#include "export_command.hpp"
#include "report_command.hpp"
#include "autocorrelation_command.hpp"
#include "cuts_command.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <optional>

using namespace wiredem::client;

int main(int argc, char** argv)
{
    CLI::App app{"wiredem: submit triaxial campaigns to a wiredem server, follow them and fetch their results;\n"
                 "or run one locally. Server: --server URL, else $WIREDEM_SERVER, else http://127.0.0.1:8080."};
    app.require_subcommand(1);
    app.fallthrough();  // global options are accepted after the subcommand too

    GlobalOptions g;
    double timeout_s = 30.0;
    app.add_option("--server", g.server_url, "server URL, http://HOST[:PORT][/PREFIX] (env WIREDEM_SERVER)");
    app.add_option("--token-file", g.token_file, "file with the bearer token (env WIREDEM_TOKEN_FILE)");
    app.add_flag("--json", g.json, "machine-readable output: the server's JSON documents");
    app.add_option("--timeout", timeout_s, "seconds for each network operation")->capture_default_str()->check(CLI::Range(0.1, 3600.0));

    std::string job_file;
    std::string id;
    std::string out_dir;
    WaitOptions wait_opts;
    double wait_timeout = 0.0;
    auto add_wait_options = [&](CLI::App* cmd) {
        cmd->add_option("--interval", wait_opts.interval_s, "seconds between polls")->capture_default_str()->check(CLI::Range(0.05, 3600.0));
        cmd->add_option("--wait-timeout", wait_timeout, "give up waiting after this many seconds (exit 10)")->check(CLI::PositiveNumber);
    };

    auto* submit = app.add_subcommand("submit", "validate JOB.json, queue it, print the job id");
    submit->add_option("job", job_file, "job spec (docs/job-spec.md)")->required();
    bool submit_wait = false;
    submit->add_flag("--wait", submit_wait, "then wait for the job like `wait`");
    add_wait_options(submit);

    auto* status = app.add_subcommand("status", "state, stage, progress and times of a job");
    status->add_option("id", id, "job id")->required();

    auto* wait = app.add_subcommand("wait", "follow a job until it ends (progress bar on a terminal)");
    wait->add_option("id", id, "job id")->required();
    add_wait_options(wait);

    auto* list = app.add_subcommand("list", "jobs, newest first");
    std::string state;
    int limit = 20;
    bool all = false;
    list->add_option("--state", state, "only jobs in this state")
        ->check(CLI::IsMember({"queued", "preparing", "running", "succeeded", "failed", "cancelled"}));
    list->add_option("--limit", limit, "jobs per page")->capture_default_str()->check(CLI::Range(1, 500));
    list->add_flag("--all", all, "every page");

    auto* cancel = app.add_subcommand("cancel", "cancel a queued or running job");
    cancel->add_option("id", id, "job id")->required();

    auto* summary = app.add_subcommand("summary", "results table of a succeeded job");
    summary->add_option("id", id, "job id")->required();

    auto* fetch = app.add_subcommand("fetch", "download summary.json and result.h5 (resumes a partial download)");
    fetch->add_option("id", id, "job id")->required();
    fetch->add_option("-o,--output", out_dir, "directory for the files")->required();

    auto* health = app.add_subcommand("health", "check that the server answers");

    LocalStage local;
    const auto stage_options = [&](CLI::App* sub) {
        sub->add_option("--threads", local.threads, "engine threads (0: every core)")->capture_default_str();
        sub->add_option("--progress", local.progress, "progress on stdout: text or json (one object per line)")
            ->capture_default_str()->check(CLI::IsMember({"text", "json"}));
        sub->add_option("--lock-wait", local.lock_wait_s,
               "seconds to wait when another process runs the same stage of the directory, before giving up")
            ->capture_default_str()->check(CLI::Range(0.0, 86400.0));
    };
    const auto checkpoint_option = [&](CLI::App* sub) {
        sub->add_option("--checkpoint-interval", local.checkpoint_interval_s,
               "seconds of wall time between checkpoints of a running preparation or test (0: none); killed, it continues from the last")
            ->capture_default_str()->check(CLI::Range(0.0, 1e6));
    };
    const auto specimen_from_option = [&](CLI::App* sub) {
        sub->add_option("--specimen-from", local.specimen_from,
               "a prepared job directory whose specimen to take instead of pouring one; its job must prepare the same "
               "specimen (job.json equal but for triaxial, name, comment and engine.threads)")
            ->check(CLI::ExistingDirectory);
    };
    auto* run = app.add_subcommand("run", "run a job here, without a server (continues what DIR holds)");
    run->add_option("job", local.job_file, "job spec")->required();
    run->add_option("-o,--output", local.dir, "job directory: summary.json, result.h5 and the stages' files")->required();
    stage_options(run);
    checkpoint_option(run);
    specimen_from_option(run);

    auto* prepare = app.add_subcommand("prepare", "prepare a job's specimen into a job directory (stage 1 of run)");
    prepare->add_option("job", local.job_file, "job spec")->required();
    prepare->add_option("-o,--output", local.dir, "job directory")->required();
    stage_options(prepare);
    checkpoint_option(prepare);
    specimen_from_option(prepare);

    auto* test = app.add_subcommand("test", "run one test of a prepared job directory (stage 2 of run)");
    test->add_option("dir", local.dir, "job directory (wiredem prepare)")->required();
    auto* by_index = test->add_option("--index", local.index, "the test: index of its confining pressure in the job (0 first)");
    auto* by_pressure = test->add_option("--pressure", local.pressure_pa, "the test: its confining pressure [Pa]");
    auto* free_standing = test->add_flag("--free-standing", local.free_standing,
        "the test: the job's free-standing test (free_standing.enabled), which `run` and `analyse` run after the triaxial tests");
    by_index->excludes(by_pressure);
    free_standing->excludes(by_index)->excludes(by_pressure);
    test->callback([&] {
        if (!local.index && !local.pressure_pa && !local.free_standing)
            throw CLI::ValidationError("test", "give --index, --pressure or --free-standing");
    });
    stage_options(test);
    checkpoint_option(test);

    auto* analyse = app.add_subcommand("analyse", "write result.h5 and summary.json from a job directory's tests (stage 3)");
    analyse->add_option("dir", local.dir, "job directory")->required();
    stage_options(analyse);
    checkpoint_option(analyse); // it runs the free-standing test when that has not run

    auto* study = app.add_subcommand("study", "parameter studies: a base job and the fields to vary (docs/studies.md)");
    study->require_subcommand(1);
    std::filesystem::path study_file;
    std::size_t study_jobs = 1, max_points = wiredem::api::default_max_study_points;
    auto* study_run = study->add_subcommand("run", "run a study here: each point's campaign in DIR/points/K, then DIR/summary.json and .csv");
    study_run->add_option("study", study_file, "study document")->required();
    study_run->add_option("-o,--output", local.dir, "study directory (run again to continue it)")->required();
    study_run->add_option("--jobs", study_jobs, "points run at once, the threads shared among them")
        ->capture_default_str()->check(CLI::Range(std::size_t{1}, std::size_t{1024}));
    study_run->add_option("--max-points", max_points, "refuse a study with more points")
        ->capture_default_str()->check(CLI::Range(std::size_t{1}, std::size_t{1000000}));
    stage_options(study_run);
    checkpoint_option(study_run);

    auto* study_check = study->add_subcommand("check", "validate STUDY.json (every point as a job) and list its points; nothing runs");
    study_check->add_option("study", study_file, "study document")->required();
    study_check->add_option("--max-points", max_points, "refuse a study with more points")
        ->capture_default_str()->check(CLI::Range(std::size_t{1}, std::size_t{1000000}));
    auto* study_submit = study->add_subcommand("submit", "validate STUDY.json (every point as a job), queue its jobs, print the study id");
    study_submit->add_option("study", study_file, "study document")->required();
    bool study_submit_wait = false;
    study_submit->add_flag("--wait", study_submit_wait, "then wait for the study like `study wait`");
    add_wait_options(study_submit);
    auto* study_status = study->add_subcommand("status", "a study's jobs counted by state, and each point's job");
    study_status->add_option("id", id, "study id")->required();
    auto* study_wait = study->add_subcommand("wait", "follow a study until all its jobs have ended");
    study_wait->add_option("id", id, "study id")->required();
    add_wait_options(study_wait);
    auto* study_cancel = study->add_subcommand("cancel", "cancel every job of a study that has not ended");
    study_cancel->add_option("id", id, "study id")->required();
    auto* study_delete = study->add_subcommand("delete", "delete a study whose jobs have all ended, with its jobs and their files");
    study_delete->add_option("id", id, "study id")->required();
    auto* study_summary = study->add_subcommand("summary", "phi and c over the seeds and per point");
    study_summary->add_option("id", id, "study id")->required();
    bool study_csv = false;
    study_summary->add_flag("--csv", study_csv, "the points as CSV");
    auto* study_fetch = study->add_subcommand("fetch", "summary.json, summary.csv and each succeeded point's files");
    study_fetch->add_option("id", id, "study id")->required();
    study_fetch->add_option("-o,--output", out_dir, "directory for the files")->required();

    auto* export_xdmf = app.add_subcommand("export-xdmf", "write the XDMF sidecar of a result.h5, for ParaView");
    std::string h5_file, xdmf_file;
    export_xdmf->add_option("result", h5_file, "result file (docs/results.md)")->required();
    export_xdmf->add_option("-o,--output", xdmf_file, "XDMF file (default: RESULT with the extension .xdmf)");

    auto* autocorrelation = app.add_subcommand("autocorrelation",
        "the autocorrelation of a result file's wire strains at a snapshot, as JSON (what the server's route answers)");
    std::string ac_test;
    std::optional<long long> ac_snapshot;
    autocorrelation->add_option("result", h5_file, "result file (docs/results.md)")->required();
    autocorrelation->add_option("--test", ac_test, "test group, e.g. sigma3_20000 (default: the highest pressure)");
    autocorrelation->add_option("--snapshot", ac_snapshot, "snapshot index k (default: the test's last)");

    auto* cuts = app.add_subcommand("cuts",
        "where to cut the wire: the places of lowest segment strain of a reference test in a result file, as JSON for specimen.wire.cuts_at_m");
    CutsRequest cuts_request;
    cuts->add_option("result", cuts_request.result, "result.h5, or the output folder that holds it (docs/results.md)")->required();
    cuts->add_option("--count", cuts_request.count, "how many cuts N")->required()->check(CLI::Range(1, 1000000));
    cuts->add_option("--test", cuts_request.test,
        "reference test: a test group, e.g. sigma3_20000, or free_standing (default: the highest pressure)");
    cuts->add_option("--at-strain", cuts_request.at_strain,
        "the snapshot nearest this axial strain (default: nearest the test's peak; the free-standing test's peak snapshot)");
    cuts->add_option("--min-spacing-m", cuts_request.min_spacing_m,
        "cuts at least this far apart and from the wire's ends [m] (default: the wire's length per loop about the axis)");

    auto* report = app.add_subcommand("report", "write OUT/report.html: the results of a run's output folder as one page that opens without a server");
    std::string report_dir, report_file, web_dir;
    report->add_option("out", report_dir, "output folder of wiredem run or wiredem fetch (summary.json, result.h5)")->required();
    report->add_option("-o,--output", report_file, "HTML file (default: OUT/report.html)");
    report->add_option("--web-dir", web_dir, "the installed web page (default: share/wiredem/web beside the binary's folder)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) {  // --help, --version
            app.exit(e);
            return exit_code::ok;
        }
        // One line, as every other error (CLI11's own adds "Run with --help …").
        std::cerr << "wiredem: " << e.what() << " (wiredem --help lists the commands and options)" << std::endl;
        return exit_code::usage;
    }
    g.timeout = std::chrono::milliseconds(static_cast<long long>(timeout_s * 1000.0));
    if (wait_timeout > 0) wait_opts.timeout_s = wait_timeout;

    try {
        if (*submit) return cmd_submit(g, job_file, submit_wait, wait_opts);
        if (*status) return cmd_status(g, id);
        if (*wait) return cmd_wait(g, id, wait_opts);
        if (*list) return cmd_list(g, state, limit, all);
        if (*cancel) return cmd_cancel(g, id);
        if (*summary) return cmd_summary(g, id);
        if (*fetch) return cmd_fetch(g, id, out_dir);
        if (*health) return cmd_health(g);
        if (*run) return cmd_run(local);
        if (*prepare) return cmd_prepare(local);
        if (*test) return cmd_test(local);
        if (*analyse) return cmd_analyse(local);
        if (*study_run) return cmd_study_run(study_file, local, study_jobs, max_points);
        if (*study_check) return cmd_study_check(g, study_file, max_points);
        if (*study_submit) return cmd_study_submit(g, study_file, study_submit_wait, wait_opts);
        if (*study_status) return cmd_study_status(g, id);
        if (*study_wait) return cmd_study_wait(g, id, wait_opts);
        if (*study_cancel) return cmd_study_cancel(g, id);
        if (*study_delete) return cmd_study_delete(g, id);
        if (*study_summary) return cmd_study_summary(g, id, study_csv);
        if (*study_fetch) return cmd_study_fetch(g, id, out_dir);
        if (*export_xdmf) return cmd_export_xdmf(h5_file, xdmf_file);
        if (*report) return cmd_report(report_dir, report_file, web_dir);
        if (*autocorrelation) return cmd_autocorrelation(h5_file, ac_test, ac_snapshot);
        if (*cuts) return cmd_cuts(cuts_request);
    } catch (const CommandError& e) {
        std::cerr << "wiredem: " << e.what() << std::endl;
        return e.code;
    } catch (const std::exception& e) {
        std::cerr << "wiredem: " << e.what() << std::endl;
        return exit_code::local_io;
    }
    return exit_code::usage;
}
