#!/usr/bin/env bash
# Build the VS Code extension into editors/vscode/robocop-mission.vsix: install the
# client library and the packaging tool from the npm registry, check the grammar
# against every mission, package.
set -euo pipefail
cd "$(dirname "$0")"
npm install --no-audit --no-fund --loglevel=error
npm test
npm run package
echo "built $(pwd)/robocop-mission.vsix"
