// three-mesh-bvh's side of the peer benchmark (tools/peer-three-mesh-bvh.sh): read the mesh
// raystream-peer-tmb --mesh-out wrote, build three-mesh-bvh's MeshBVH over it as a user would
// (new MeshBVH(geometry, {strategy}): every other option its default), pack it with its own
// MeshBVHUniformStruct and write what a shader needs, unchanged:
//   textures.txt   one "NAME FORMAT WIDTH HEIGHT" per texture of the BVH struct
//   NAME.bin       its texels (index, position, bvhBounds, bvhContents)
//   bvh.glsl       BVHShaderGLSL's common_functions, bvh_struct_definitions, bvh_ray_functions
//   slots.bin      uint32 per triangle slot of the packed index: the scene's triangle id
//                  (the build reorders the index buffer in place)
//   info.txt       package version, strategy, nodes, build time
// Run from a folder whose node_modules holds three and three-mesh-bvh (installed there at
// benchmark time only). Usage: node build_bvh.mjs MESH OUTDIR [center|average|sah]
import { readFileSync, writeFileSync } from 'node:fs';
import { BufferGeometry, BufferAttribute } from 'three';
import {
	MeshBVH, MeshBVHUniformStruct, BVHShaderGLSL, CENTER, AVERAGE, SAH,
} from 'three-mesh-bvh';

const [ meshPath, outDir, strategyName = 'center' ] = process.argv.slice( 2 );
const strategies = { center: CENTER, average: AVERAGE, sah: SAH };
if ( ! meshPath || ! outDir || ! ( strategyName in strategies ) ) {

	console.error( 'usage: node build_bvh.mjs MESH OUTDIR [center|average|sah]' );
	process.exit( 2 );

}

// RSMESH1\0, uint32 vertex count, uint32 triangle count, float32 xyz..., uint32 abc...
const bytes = readFileSync( meshPath );
if ( bytes.length < 16 || bytes.toString( 'latin1', 0, 8 ) !== 'RSMESH1\0' ) {

	console.error( `${meshPath}: not a raystream-peer-tmb mesh` );
	process.exit( 1 );

}

const vertexCount = bytes.readUInt32LE( 8 ), triangleCount = bytes.readUInt32LE( 12 );
if ( bytes.length !== 16 + 12 * vertexCount + 12 * triangleCount ) {

	console.error( `${meshPath}: ${bytes.length} bytes do not fit its counts` );
	process.exit( 1 );

}

const body = bytes.buffer.slice( bytes.byteOffset + 16, bytes.byteOffset + bytes.length );
const positions = new Float32Array( body, 0, 3 * vertexCount );
const index = new Uint32Array( body.slice( 12 * vertexCount ) );
const original = new Map();
for ( let t = 0; t < triangleCount; t ++ ) {

	const key = `${index[ 3 * t ]},${index[ 3 * t + 1 ]},${index[ 3 * t + 2 ]}`;
	( original.get( key ) || original.set( key, [] ).get( key ) ).push( t );

}

const geometry = new BufferGeometry();
geometry.setAttribute( 'position', new BufferAttribute( positions, 3 ) );
geometry.setIndex( new BufferAttribute( index, 1 ) );
const t0 = performance.now();
const bvh = new MeshBVH( geometry, { strategy: strategies[ strategyName ] } );
const buildMs = performance.now() - t0;
const uniforms = new MeshBVHUniformStruct();
uniforms.updateFrom( bvh );

// the slot -> scene triangle map, from the reordered index (equal triples: first come first)
const packed = geometry.index.array;
const slots = new Uint32Array( triangleCount );
for ( let s = 0; s < triangleCount; s ++ ) {

	const list = original.get( `${packed[ 3 * s ]},${packed[ 3 * s + 1 ]},${packed[ 3 * s + 2 ]}` );
	if ( ! list || list.length === 0 ) {

		console.error( `slot ${s}: triangle not in the mesh` );
		process.exit( 1 );

	}

	slots[ s ] = list.shift();

}

let lines = '';
for ( const name of [ 'index', 'position', 'bvhBounds', 'bvhContents' ] ) {

	const tex = uniforms[ name ];
	const { data, width, height } = tex.image;
	lines += `${name} ${tex.internalFormat} ${width} ${height}\n`;
	writeFileSync( `${outDir}/${name}.bin`, new Uint8Array( data.buffer, data.byteOffset, data.byteLength ) );

}

writeFileSync( `${outDir}/textures.txt`, lines );
writeFileSync( `${outDir}/slots.bin`, new Uint8Array( slots.buffer ) );
writeFileSync( `${outDir}/bvh.glsl`, BVHShaderGLSL.common_functions + BVHShaderGLSL.bvh_struct_definitions + BVHShaderGLSL.bvh_ray_functions );
const version = JSON.parse( readFileSync( new URL( './node_modules/three-mesh-bvh/package.json', import.meta.url ) ) ).version;
const nodes = bvh._roots[ 0 ].byteLength / 32;
writeFileSync( `${outDir}/info.txt`, `three-mesh-bvh ${version} strategy ${strategyName} nodes ${nodes} build_ms ${buildMs.toFixed( 1 )}\n` );
