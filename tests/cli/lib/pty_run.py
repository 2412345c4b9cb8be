"""Runs a command under a pseudo-terminal 80 columns wide, as a person's terminal would be."""
import fcntl
import os
import pty
import struct
import termios
import time


def run(argv):
    """Returns (exit code, [(seconds since start, bytes read)])."""
    pid, fd = pty.fork()
    if pid == 0:
        os.environ["COLUMNS"] = "80"
        os.execv(argv[0], argv)
    fcntl.ioctl(fd, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 80, 0, 0))
    start = time.monotonic()
    chunks = []
    while True:
        try:
            data = os.read(fd, 65536)
        except OSError:
            break
        if not data:
            break
        chunks.append((time.monotonic() - start, data))
    _, status = os.waitpid(pid, 0)
    return os.waitstatus_to_exitcode(status), chunks
