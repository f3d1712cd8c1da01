"""A standalone HTML replay: meshcat's browser client, then the scene and animation
commands, decoded and applied in order when the page loads (no server needed).

The commands are stored as a JSON list of base64 msgpack blobs in the element
``<script id="meshcat-commands">``. Open the file with ``#t=SECONDS`` appended to its
address to show the replay paused at that time after the first frame.
"""

from __future__ import annotations

import base64
import html
import json
import re
from pathlib import Path

import meshcat

from .commands import pack, unpack
from .errors import ViewerError

CLIENT = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
COMMANDS_ID = "meshcat-commands"

_PAGE = """<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
body {{ margin: 0; }}
#meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
</style>
</head>
<body>
<div id="meshcat-pane"></div>
<script>
{client}
</script>
<script type="application/json" id="{commands_id}">{commands}</script>
<script>
(function () {{
  var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
  var commands = JSON.parse(document.getElementById("{commands_id}").textContent);
  commands.forEach(function (encoded) {{
    var text = atob(encoded);
    var bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; i++) {{ bytes[i] = text.charCodeAt(i); }}
    viewer.handle_command_bytearray(bytes);
  }});
  var at = /[#&]t=([0-9.eE+-]+)/.exec(window.location.hash);
  if (at) {{
    viewer.animator.pause();
    viewer.animator.seek(parseFloat(at[1]));
  }}
  window.meshcat_viewer = viewer;
}})();
</script>
</body>
</html>
"""


def replay_html(commands: list, title: str) -> str:
    """The standalone page that applies ``commands`` (lowered, in order) on load.

    Args:
        commands: Lowered Meshcat commands: the scene first, the animation last.
        title: The page title.
    """
    encoded = [base64.b64encode(pack(command)).decode("ascii") for command in commands]
    return _PAGE.format(title=html.escape(title), client=CLIENT.read_text(encoding="utf-8"),
                        commands_id=COMMANDS_ID, commands=json.dumps(encoded))


def write_replay(path: str | Path, commands: list, title: str) -> Path:
    """Write :func:`replay_html` to ``path`` (folders created); returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(replay_html(commands, title), encoding="utf-8")
    return path


def read_replay(path: str | Path) -> list:
    """The lowered Meshcat commands stored in a replay file, in order.

    Raises:
        ViewerError: the file holds no stored commands.
    """
    text = Path(path).read_text(encoding="utf-8")
    match = re.search(rf'<script type="application/json" id="{COMMANDS_ID}">(.*?)</script>',
                      text, re.DOTALL)
    if match is None:
        raise ViewerError(f"{path}: not a replay file (no stored Meshcat commands)")
    return [unpack(base64.b64decode(blob)) for blob in json.loads(match.group(1))]
