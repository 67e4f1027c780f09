#!/usr/bin/python3
"""geovor serve on a port already in use: exit 4 with the address named. Usage: GEOVOR SITES"""
import socket
import subprocess
import sys

s = socket.socket()
s.bind(("127.0.0.1", 0))
s.listen()
p = subprocess.run([sys.argv[1], "serve", sys.argv[2], "--port", str(s.getsockname()[1])],
                   capture_output=True, text=True, timeout=60)
sys.stderr.write(p.stderr)
sys.exit(p.returncode)
