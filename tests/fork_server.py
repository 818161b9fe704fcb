"""spam-ark's runs as forked children of the fork server tests/fuzz_server.c, which has loaded
spam-ark's objects and the hundred-odd shared libraries PETSc brings once: a start refused at
option parsing costs about half the CPU time of a start of spam-ark (the dynamic loader's
binding of symbols is done once). Each child calls spam-ark's entry (src/app/program.c) as
main() would, with the run's arguments, directory, environment and address-space limit, and
exits with its code; MPI and PETSc start from nothing in it, and atexit handlers and the
sanitizers' exit checks (LeakSanitizer's scan included, unless the environment turns it off)
run as in a process of its own. The fuzz corpus (run_fuzz.py) and the bad-input tests use it."""
import os
import subprocess


def server_path(spam_ark):
    """The fork server built with spam_ark (SPAM_FUZZ_SERVER, or tests/fuzz_server in its build
    directory), or None: SPAM_FUZZ_EXEC=1 asks for a start of spam-ark for each run, and a
    build without the server has none."""
    if os.environ.get("SPAM_FUZZ_EXEC") == "1":
        return None
    path = os.environ.get("SPAM_FUZZ_SERVER") or os.path.join(os.path.dirname(os.path.abspath(spam_ark)), "tests", "fuzz_server")
    return path if os.access(path, os.X_OK) else None


def needs_exec(args):
    """A run whose outcome may depend on which executable runs it, which in the server's child
    is the server: a relative -options_file that is not in the working directory is looked up
    next to /proc/self/exe (argv_check.c); a file under /proc/self describes the process."""
    args = [os.fsdecode(x) if isinstance(x, bytes) else str(x) for x in args]
    return (any(o == "-options_file" and not os.path.isabs(v) for o, v in zip(args, args[1:]))
            or any(x.startswith("/proc/self/") for x in args))


class Server:
    """One fork server (one run at a time); run() sends it a run and waits for its end."""

    def __init__(self, path, program, env, cwd):
        self.program, self.env = os.path.abspath(program), env
        self.p = subprocess.Popen([path], stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env, cwd=cwd)

    def run(self, args, cwd, env, out_path, err_path, timeout, limit=0):
        """The run's exit code (negative: the signal that ended it) or "timeout". Its stdout and
        stderr go to out_path and err_path, stdin is /dev/null; limit: the address space in
        bytes (0: none)."""
        # The environment as the server's child would not have it already: the assignments
        # that differ from the server's own, and the names to unset.
        delta = [f"{k}={v}" for k, v in env.items() if self.env.get(k) != v] + [k for k in self.env if k not in env]
        fields = [cwd, out_path, err_path, str(timeout), str(limit), str(len(delta))] + delta
        fields += [str(len(args) + 1), self.program] + list(args)
        self.p.stdin.write(b"".join((x if isinstance(x, bytes) else os.fsencode(str(x))) + b"\0" for x in fields))
        self.p.stdin.flush()
        answer = self.p.stdout.readline().decode().split()
        if not answer:
            raise RuntimeError(f"the fork server ended (exit {self.p.wait()})")
        if answer[0] == "timeout":
            return "timeout"
        return int(answer[1]) if answer[0] == "exit" else -int(answer[1])

    def close(self):
        self.p.stdin.close()
        return self.p.wait()
