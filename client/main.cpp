// wiredem: the command-line client of wiredem-server, and the local runner
// (`wiredem run`). Errors end as one line "wiredem: …" on stderr and an exit
// code from exit_codes.hpp (table in docs/client.md).
#include "commands.hpp"
#include "exit_codes.hpp"
#include "export_command.hpp"
#include "report_command.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

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

    auto* run = app.add_subcommand("run", "run a job here, without a server");
    run->add_option("job", job_file, "job spec")->required();
    run->add_option("-o,--output", out_dir, "directory for summary.json and result.h5")->required();
    unsigned threads = 0;
    std::string progress = "text";
    run->add_option("--threads", threads, "engine threads (0: every core)")->capture_default_str();
    run->add_option("--progress", progress, "progress on stdout: text or json (one object per line)")
        ->capture_default_str()->check(CLI::IsMember({"text", "json"}));

    auto* export_xdmf = app.add_subcommand("export-xdmf", "write the XDMF sidecar of a result.h5, for ParaView");
    std::string h5_file, xdmf_file;
    export_xdmf->add_option("result", h5_file, "result file (docs/results.md)")->required();
    export_xdmf->add_option("-o,--output", xdmf_file, "XDMF file (default: RESULT with the extension .xdmf)");

    auto* report = app.add_subcommand("report", "write OUT/report.html: the results of a run's output folder as one page that opens without a server");
    std::string report_dir, report_file, web_dir;
    report->add_option("out", report_dir, "output folder of wiredem run or wiredem fetch (summary.json, result.h5)")->required();
    report->add_option("-o,--output", report_file, "HTML file (default: OUT/report.html)");
    report->add_option("--web-dir", web_dir, "the installed web page (default: share/wiredem/web beside the binary's folder)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? exit_code::ok : exit_code::usage;
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
        if (*run) return cmd_run(job_file, out_dir, threads, progress);
        if (*export_xdmf) return cmd_export_xdmf(h5_file, xdmf_file);
        if (*report) return cmd_report(report_dir, report_file, web_dir);
    } catch (const CommandError& e) {
        std::cerr << "wiredem: " << e.what() << std::endl;
        return e.code;
    } catch (const std::exception& e) {
        std::cerr << "wiredem: " << e.what() << std::endl;
        return exit_code::local_io;
    }
    return exit_code::usage;
}
