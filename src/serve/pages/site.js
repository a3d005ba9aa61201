// Where the pages' data comes from: null under `vk-render serve` (its API answers); a folder that
// `vk-render site` wrote holds its own copy of this file, naming the files it wrote in the API's place
// (src/serve/site/mod.rs), and nothing else of the pages differs.
export const SITE = null;
