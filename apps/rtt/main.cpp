// The `rtt` program. Errors of any kind end here as one line on stderr and a non-zero exit:
// rtt::Error (bad input), CLI11 parse errors (bad options), std::bad_alloc.
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "cli_hints.h"
#include "commands.h"
#include "mpi_render.h"
#include "rtt/error.h"
#include "rtt/isa.h"
#include "rtt/version.h"

namespace {

int fail(std::string message, int code) {
    for (char& c : message)
        if (c == '\n' || c == '\r') c = ' ';
    // Under mpirun a failure on any rank stops every rank, naming the rank.
    if (rtt::cli::mpi_distributed()) rtt::cli::mpi_abort(message);
    std::fprintf(stderr, "rtt: error: %s\n", message.c_str());
    rtt::cli::mpi_finish();
    return code;
}

// "rtt 0.2.0 (avx512 kernels of sse4.2, avx2, avx512)": the version and which kernels run.
std::string version_line() {
    std::string isas;
    for (rtt::Isa isa : rtt::runnable_isas())
        isas += (isas.empty() ? "" : ", ") + std::string(rtt::isa_name(isa));
    return std::string("rtt ") + rtt::version_string + " (" +
           std::string(rtt::isa_name(rtt::active_isa())) + " kernels; this CPU and build run " +
           isas + ")";
}

}  // namespace

int main(int argc, char** argv) {
    rtt::cli::mpi_start(argc, argv);
    CLI::App app{
        "rtt: ray tracing with SIMD shaft culling (Dmitriev, Havran, Seidel 2004).\n"
        "Without a subcommand, renders the built-in scene 'room' to room.png and prints\n"
        "the statistics."};
    app.name("rtt");
    app.require_subcommand(0, 1);
    try {
        app.set_version_flag("--version", version_line());  // also checks RTT_ISA
    } catch (const rtt::Error& e) {
        return fail(e.what(), 2);
    }
    // Global options may follow the subcommand too: `rtt render --isa avx2 ...`.
    app.fallthrough();
    app.add_option_function<std::string>(
           "--isa", [](const std::string& isa) { rtt::limit_isa(rtt::parse_isa(isa)); },
           "Cap the SIMD kernels: sse4.2, avx2 or avx512 (default: the widest this CPU runs, or "
           "the environment's RTT_ISA). Results are the same bits; only speed differs.")
        ->check(CLI::IsMember({"sse4.2", "avx2", "avx512"}));
    rtt::cli::add_render_command(app);
    rtt::cli::add_info_command(app);
    rtt::cli::add_scenes_command(app);
    rtt::cli::add_bench_command(app);
#ifdef RTT_HAVE_VIEWER
    rtt::cli::add_view_command(app);
#endif
    try {
        app.parse(argc, argv);  // runs the chosen subcommand's callback
        if (app.get_subcommands().empty()) rtt::cli::run_default_job();
        rtt::cli::mpi_finish();
        return 0;
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) {  // --help, --version
            rtt::cli::mpi_finish();
            return rtt::cli::mpi_rank() == 0 ? app.exit(e) : 0;
        }
        return fail(std::string(e.what()) + "." + rtt::cli::hint_for(app, e), 2);
    } catch (const rtt::Error& e) {
        return fail(e.what(), 1);
    } catch (const std::bad_alloc&) {
        return fail("out of memory", 1);
    } catch (const std::exception& e) {
        return fail(e.what(), 1);
    }
}
