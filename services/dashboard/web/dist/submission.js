// What "Submit scene" sends: among the files a user chose (or the folder's files), the one
// scene (.json) and the others base64 by the name the server matches against the scene's
// paths (uploads.go: its path within the folder, or its name).
export class SubmissionError extends Error {
}
/** The scene file and every other file, base64 by its path in the folder or its name. */
export async function readSubmission(chosen) {
    const pathOf = (f) => f.webkitRelativePath || f.name;
    const scenes = chosen.filter((f) => f.name.toLowerCase().endsWith(".json"));
    if (scenes.length !== 1) {
        throw new SubmissionError(scenes.length === 0
            ? `none of the ${chosen.length} files chosen is a scene (.json): choose the scene file with its files`
            : `choose one scene: ${scenes.map(pathOf).join(", ")} are all .json files`);
    }
    const scene = scenes[0];
    const files = {};
    for (const f of chosen)
        if (f !== scene)
            files[pathOf(f)] = base64(new Uint8Array(await f.arrayBuffer()));
    return { scene, files };
}
function base64(bytes) {
    let s = "";
    const chunk = 0x8000; // String.fromCharCode takes that many arguments safely
    for (let i = 0; i < bytes.length; i += chunk)
        s += String.fromCharCode(...bytes.subarray(i, i + chunk));
    return btoa(s);
}
