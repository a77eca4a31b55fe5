// The third-party browser code of `crslab serve`, bundled into one file that sets `window.CrsVendor`
// (see tools/serve_vendor/build.sh and crslab/serve/static/vendor/README.md).
import { EditorView, basicSetup } from "codemirror";
import { EditorState } from "@codemirror/state";
import { keymap } from "@codemirror/view";
import { indentWithTab } from "@codemirror/commands";
import { cpp } from "@codemirror/lang-cpp";
import { setDiagnostics, lintGutter } from "@codemirror/lint";
import { Terminal } from "@xterm/xterm";
import {
  Scene, PerspectiveCamera, WebGLRenderer, Color, AmbientLight, DirectionalLight, Group, Mesh,
  MeshStandardMaterial, CapsuleGeometry, CylinderGeometry, SphereGeometry, BoxGeometry, GridHelper,
  Raycaster, Vector2, Vector3, Quaternion, Plane, Spherical,
} from "three";

window.CrsVendor = {
  EditorView, EditorState, basicSetup, keymap, indentWithTab, cpp, setDiagnostics, lintGutter, Terminal,
  THREE: {
    Scene, PerspectiveCamera, WebGLRenderer, Color, AmbientLight, DirectionalLight, Group, Mesh,
    MeshStandardMaterial, CapsuleGeometry, CylinderGeometry, SphereGeometry, BoxGeometry, GridHelper,
    Raycaster, Vector2, Vector3, Quaternion, Plane, Spherical,
  },
};
